#include "daemon/imu_parts.hpp"

#include "daemon/driver_params.hpp"

namespace tumble::daemon {

void report_imu(const mti::MtiStats& stats, const mti::TimeMapper& clock, const ImuSampleGate& gate,
                PipelineCounters& counters) {
  constexpr auto relaxed = std::memory_order_relaxed;
  counters.imu_rejected_samples.store(gate.rejected(), relaxed);
  counters.imu_frames.store(static_cast<std::int64_t>(stats.frames.frames), relaxed);
  counters.imu_bad_frames.store(static_cast<std::int64_t>(stats.frames.bad_frames()), relaxed);
  counters.imu_gaps.store(static_cast<std::int64_t>(stats.sample_time_gaps + stats.packet_counter_gaps), relaxed);
  counters.imu_duplicate_frames.store(static_cast<std::int64_t>(stats.duplicate_frames), relaxed);
  counters.imu_out_of_order_frames.store(static_cast<std::int64_t>(stats.out_of_order_frames), relaxed);
  if (clock.ready()) {
    counters.imu_clock.offset_s.store(clock.offset_s(), relaxed);
    counters.imu_clock.drift_ppm.store(clock.drift() * 1e6, relaxed);
    counters.imu_clock.jitter_s.store(clock.jitter_s(), relaxed);
  }
}

void ImuFaultLog::check(const mti::MtiStats& stats, double now_s) {
  // Reading starts mid-frame: bytes before the first good frame are no fault.
  if (stats.frames.frames == 0) discarded_bytes_ = stats.frames.bytes_discarded;
  if (stats.frames.bytes_discarded > discarded_bytes_) {
    discarded_bytes_ = stats.frames.bytes_discarded;
    log_.warn("imu garbage", now_s, "imu: garbage on the serial line: {} bytes skipped between frames so far",
              discarded_bytes_);
  }
  if (stats.duplicate_frames > duplicates_) {
    duplicates_ = stats.duplicate_frames;
    log_.warn("imu duplicate", now_s, "imu: duplicated frame (repeated PacketCounter) dropped; {} so far",
              duplicates_);
  }
  if (stats.out_of_order_frames > out_of_order_) {
    out_of_order_ = stats.out_of_order_frames;
    log_.warn("imu out of order", now_s, "imu: frame out of order (older PacketCounter) dropped; {} so far",
              out_of_order_);
  }
}

MtiByteDecoder::MtiByteDecoder(const ImuConfig& config)
    : stream_(imu_stream_options(config)), gate_(imu_limits(config)) {}

void MtiByteDecoder::decode(const ImuBytes& bytes, const std::function<void(const ImuSample&)>& emit) {
  samples_.clear();
  stream_.feed(bytes.bytes, bytes.arrival_s, samples_);
  faults_.check(stream_.stats(), bytes.arrival_s);
  for (const ImuSample& sample : samples_) gate_.pass(sample, bytes.arrival_s, emit);
}

void MtiByteDecoder::report(PipelineCounters& counters) const {
  report_imu(stream_.stats(), stream_.time_mapper(), gate_, counters);
}

LiveImuSource::LiveImuSource(boost::asio::io_context& io, const ImuConfig& config, std::shared_ptr<SerialReads> reads)
    : reads_(std::move(reads)) {
  reads_->port = std::make_unique<mti::SerialSource>(
      io, serial_source_options(config), [this](const ImuSample& sample) { reads_->samples.push_back(sample); });
  // The source reports a read after decoding it: the samples above are its own.
  reads_->port->set_read_handler([this](std::int64_t arrival_ns, std::span<const std::uint8_t> bytes) {
    if (on_bytes_) on_bytes_(ImuBytes{static_cast<double>(arrival_ns) * 1e-9, bytes});
    reads_->samples.clear();
  });
}

void LiveImuSource::start(std::function<void(const ImuBytes&)> on_bytes, std::function<void()>) {
  on_bytes_ = std::move(on_bytes);  // a serial port never ends: the source reconnects
  reads_->port->start();
}

void LiveImuSource::stop() {
  reads_->port->stop();
  on_bytes_ = nullptr;
}

SerialSampleDecoder::SerialSampleDecoder(const ImuConfig& config, std::shared_ptr<SerialReads> reads)
    : reads_(std::move(reads)), gate_(imu_limits(config)) {}

void SerialSampleDecoder::decode(const ImuBytes& bytes, const std::function<void(const ImuSample&)>& emit) {
  faults_.check(reads_->port->stats(), bytes.arrival_s);
  for (const ImuSample& sample : reads_->samples) gate_.pass(sample, bytes.arrival_s, emit);
}

void SerialSampleDecoder::report(PipelineCounters& counters) const {
  report_imu(reads_->port->stats(), reads_->port->time_mapper(), gate_, counters);
}

}  // namespace tumble::daemon
