// The MTi byte stream to IMU samples: frames, MTData2 decoding, sequence
// checks, and sensor-to-host time. Shared by the serial source and replay.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "core/types.hpp"
#include "drivers/mti/frame_reader.hpp"
#include "drivers/mti/mti_stats.hpp"
#include "drivers/mti/mtdata2.hpp"
#include "drivers/mti/sequence.hpp"
#include "drivers/mti/time_mapper.hpp"

namespace tumble::mti {

struct MtiStreamOptions {
  double imu_rate_hz = 100.0;      // output period for DeltaV/DeltaQ and gap detection
  std::uint32_t baud = 115200;     // line speed: a frame spends bytes * 10 / baud on the wire
  double imu_time_offset_s = 0.0;  // calibrated residual, added to every IMU time
  double epoch_s = 0.0;            // host time of SampleTimeFine 0, for streams without arrival times
  // A sensor clock step (back, or ahead of the host clock) beyond this is a
  // device restart: the time mapping starts afresh.
  double restart_threshold_s = 1.0;
  TimeMapperOptions time_mapper;
};

class MtiStream {
 public:
  using ControlHandler = std::function<void(const XbusFrame&)>;
  // Sees each delivered sample with the message it came from and its unwrapped
  // SampleTimeFine (nullopt when the message had none), for tools that show
  // what ImuSample does not hold (sensor time, status word).
  using SampleObserver = std::function<void(const ImuSample& sample, const MtData2& message,
                                            std::optional<std::int64_t> sample_time_ticks)>;

  explicit MtiStream(MtiStreamOptions options = {});

  // Receives every frame that is not MTData2 (acks, replies, errors, wake-ups).
  void set_control_handler(ControlHandler handler) { control_ = std::move(handler); }
  void set_sample_observer(SampleObserver observer) { observer_ = std::move(observer); }
  // MTData2 is discarded (and counted) while the device is being configured.
  // drop_first_sample: the first sample after GoToMeasurement is stale.
  void set_measuring(bool measuring, bool drop_first_sample = false);
  void set_baud(std::uint32_t baud) { options_.baud = baud; }

  // One serial read that returned at host time arrival_s; IMU samples are
  // appended to out (reuse it: no allocation once it has grown).
  void feed(std::span<const std::uint8_t> read, double arrival_s, std::vector<ImuSample>& out);
  // Bytes without arrival times: sample time = epoch_s + SampleTimeFine.
  void feed_untimed(std::span<const std::uint8_t> bytes, std::vector<ImuSample>& out);
  // The end of a recording: frames hidden behind an incomplete one are still
  // decoded, the incomplete rest is counted (stats().frames.cut_off).
  void finish(std::vector<ImuSample>& out);
  // After a reconnect: partial frame, counters and time mapping start afresh.
  void restart();

  const MtiStats& stats() const { return stats_; }
  const TimeMapper& time_mapper() const { return mapper_; }
  const MtiStreamOptions& options() const { return options_; }
  // Bytes held as the start of an incomplete frame (at the end of a file: truncated).
  std::size_t buffered_bytes() const { return reader_.buffered_bytes(); }

 private:
  void drain(const double* arrival_s, std::vector<ImuSample>& out);
  void handle_mtdata2(const XbusFrame& frame, const double* frame_start_s, std::vector<ImuSample>& out);
  // The sample's host time, or false when it must be dropped.
  bool time_sample(const double* frame_start_s, double& t_s);
  void count_saturation(const ImuSample& s);

  MtiStreamOptions options_;
  FrameReader reader_;
  ControlHandler control_;
  SampleObserver observer_;
  bool measuring_ = true;
  bool drop_next_ = false;
  MtData2 message_;
  ImuSample sample_;
  SampleTimeUnwrapper unwrapper_;
  PacketCounterTracker packet_counter_;
  TimeMapper mapper_;
  bool timed_ = false;  // the last bytes came with an arrival time
  double last_arrival_s_ = 0;
  bool have_last_ = false;
  std::int64_t last_ticks_ = 0;
  double last_frame_start_s_ = 0;
  MtiStats stats_;
};

}  // namespace tumble::mti
