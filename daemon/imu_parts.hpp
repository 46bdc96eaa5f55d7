// The MTi behind the daemon's IMU seams. Replayed serial bytes are decoded by
// MtiByteDecoder. Live, the serial source configures the device and must see
// the frames itself (acks, errors, the measurement switch), so it decodes
// them; LiveImuSource hands the pipeline each read (for the recorder) and
// SerialSampleDecoder the samples the source decoded from it.
#pragma once

#include <boost/asio/io_context.hpp>
#include <functional>
#include <memory>
#include <vector>

#include "daemon/config.hpp"
#include "daemon/imu_sample_check.hpp"
#include "daemon/rate_limited_log.hpp"
#include "daemon/seams.hpp"
#include "drivers/mti/mti_stream.hpp"
#include "drivers/mti/serial_source.hpp"

namespace tumble::daemon {

void report_imu(const mti::MtiStats& stats, const mti::TimeMapper& clock, const ImuSampleGate& gate,
                PipelineCounters& counters);

// Names each fault of the serial stream in the log as it appears (data time),
// once per period and fault: garbage between frames (after the first good
// one), duplicated and late frames.
class ImuFaultLog {
 public:
  void check(const mti::MtiStats& stats, double now_s);

 private:
  std::uint64_t discarded_bytes_ = 0;
  std::uint64_t duplicates_ = 0;
  std::uint64_t out_of_order_ = 0;
  RateLimitedLog log_{1, 10.0};
};

class MtiByteDecoder : public ImuDecoder {
 public:
  explicit MtiByteDecoder(const ImuConfig& config);
  void decode(const ImuBytes& bytes, const std::function<void(const ImuSample&)>& emit) override;
  void report(PipelineCounters& counters) const override;

 private:
  mti::MtiStream stream_;
  std::vector<ImuSample> samples_;
  ImuFaultLog faults_;
  ImuSampleGate gate_;
};

// What the live source and its decoder share (both on the io thread).
struct SerialReads {
  std::unique_ptr<mti::SerialSource> port;
  std::vector<ImuSample> samples;  // decoded from the read being delivered
};

class LiveImuSource : public ImuByteSource {
 public:
  LiveImuSource(boost::asio::io_context& io, const ImuConfig& config, std::shared_ptr<SerialReads> reads);
  void start(std::function<void(const ImuBytes&)> on_bytes, std::function<void()> on_end) override;
  void stop() override;

 private:
  std::shared_ptr<SerialReads> reads_;
  std::function<void(const ImuBytes&)> on_bytes_;
};

class SerialSampleDecoder : public ImuDecoder {
 public:
  SerialSampleDecoder(const ImuConfig& config, std::shared_ptr<SerialReads> reads);
  void decode(const ImuBytes& bytes, const std::function<void(const ImuSample&)>& emit) override;
  void report(PipelineCounters& counters) const override;

 private:
  std::shared_ptr<SerialReads> reads_;
  ImuFaultLog faults_;
  ImuSampleGate gate_;
};

}  // namespace tumble::daemon
