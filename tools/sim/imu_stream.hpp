// The MTi-30's serial stream as the host reads it: one MTData2 frame per
// sample, sent after a processing latency, clocked out at the baud rate and
// picked up by tty reads of whatever size has arrived.
#pragma once

#include <cstdint>
#include <vector>

#include "drivers/mti/mtdata2_encode.hpp"
#include "tools/sim/imu_model.hpp"
#include "tools/sim/serial_line.hpp"

namespace tumble::sim {

struct ImuLinkConfig {
  int baud = 115200;
  double processing_latency_s = 0.0015;  // from the sample instant to the first byte
  double read_latency_s = 0.0002;        // host wake-up after a byte arrives (minimum)
  double read_jitter_s = 0.002;          // plus up to this much more, uniform
  mti::NumberFormat number_format = mti::NumberFormat::Float32;
  int leading_garbage_bytes = 5;   // the recording starts mid-frame
  bool leading_config_ack = false;  // a GoToMeasurement ack before the data, as after configuring
};

struct SerialRead {
  std::int64_t arrival_ns = 0;  // run time of the read
  std::vector<std::uint8_t> bytes;
};

// Bytes of one MTData2 frame in this format (for baud checks).
std::size_t mtdata2_frame_bytes(mti::NumberFormat format);

class ImuStream {
 public:
  ImuStream(const ImuConfig& imu, const ImuClock& clock, const ImuLinkConfig& link, const Eigen::Isometry3d& T_LI,
            const Motion& motion, std::uint64_t noise_seed, bool noise_enabled, double duration_s);

  // The next tty read; false once every frame of the run has been read.
  bool next(SerialRead& out);

  std::uint64_t frame_count() const { return frames_; }
  std::uint64_t clipped_count() const { return clipped_; }
  const ImuModel& model() const { return model_; }

 private:
  void queue_frames_ready_by(double t_s);
  void queue_next_frame();

  ImuLinkConfig link_;
  ImuModel model_;
  SerialLine line_;
  SensorRng read_rng_;
  double duration_s_;
  bool samples_done_ = false;
  bool have_pending_ = false;
  ImuMeasurement pending_;  // the next sample, not yet on the line
  double last_read_s_ = 0.0;
  std::uint64_t frames_ = 0;
  std::uint64_t clipped_ = 0;
};

}  // namespace tumble::sim
