#include "drivers/mti/mti_stream.hpp"

#include <stdexcept>
#include <string>

#include "drivers/mti/imu_sample.hpp"
#include "drivers/mti/message_ids.hpp"

namespace tumble::mti {

MtiStream::MtiStream(MtiStreamOptions options) : options_(options), mapper_(options.time_mapper) {
  if (!(options_.imu_rate_hz > 0)) throw std::invalid_argument("mti: imu_rate_hz must be > 0");
  if (options_.baud == 0) throw std::invalid_argument("mti: baud must be > 0");
}

void MtiStream::set_measuring(bool measuring, bool drop_first_sample) {
  measuring_ = measuring;
  drop_next_ = measuring && drop_first_sample;
}

void MtiStream::restart() {
  reader_.reset();
  unwrapper_.reset();
  packet_counter_.reset();
  mapper_.reset();
  have_last_ = false;
  drop_next_ = false;
  stats_.frames = reader_.stats();
}

void MtiStream::feed(std::span<const std::uint8_t> read, double arrival_s, std::vector<ImuSample>& out) {
  reader_.push(read);
  timed_ = true;
  last_arrival_s_ = arrival_s;
  drain(&arrival_s, out);
}

void MtiStream::feed_untimed(std::span<const std::uint8_t> bytes, std::vector<ImuSample>& out) {
  reader_.push(bytes);
  timed_ = false;
  drain(nullptr, out);
}

void MtiStream::finish(std::vector<ImuSample>& out) {
  reader_.finish();
  drain(timed_ ? &last_arrival_s_ : nullptr, out);
}

void MtiStream::drain(const double* arrival_s, std::vector<ImuSample>& out) {
  while (const auto frame = reader_.next()) {
    if (frame->mid == mid::kMtData2) {
      if (arrival_s == nullptr) {
        handle_mtdata2(*frame, nullptr, out);
      } else {
        // The read returned after this frame and every byte behind it in the
        // read had crossed the wire.
        const double on_wire_s =
            static_cast<double>(frame->frame_bytes + frame->bytes_after_in_read) * 10.0 / options_.baud;
        const double frame_start_s = *arrival_s - on_wire_s;
        handle_mtdata2(*frame, &frame_start_s, out);
      }
      continue;
    }
    ++stats_.other_frames;
    if (frame->mid == mid::kError) ++stats_.device_errors;
    if (control_) control_(*frame);
  }
  stats_.frames = reader_.stats();
}

void MtiStream::handle_mtdata2(const XbusFrame& frame, const double* frame_start_s, std::vector<ImuSample>& out) {
  if (!measuring_) {
    ++stats_.discarded_while_configuring;
    return;
  }
  if (!decode_mtdata2(frame.payload, message_, stats_.mtdata2)) return;
  if (message_.packet_counter) {
    // A frame sent twice or arriving late would feed the fuser a time going
    // backwards: dropped before it can.
    // A sample clock far back (or far ahead) is a device restart, not a late frame.
    bool restart = false;
    if (message_.sample_time_fine && have_last_) {
      const double step_s = static_cast<double>(unwrapper_.step_to(*message_.sample_time_fine)) / kSampleTimeFineHz;
      restart = step_s < -options_.restart_threshold_s ||
                (frame_start_s != nullptr &&
                 step_s > (*frame_start_s - last_frame_start_s_) + options_.restart_threshold_s);
    }
    const CounterStep step = packet_counter_.observe(*message_.packet_counter, restart);
    if (step.order == CounterOrder::Repeated) {
      ++stats_.duplicate_frames;
      return;
    }
    if (step.order == CounterOrder::Older) {
      ++stats_.out_of_order_frames;
      return;
    }
    if (step.missing > 0) {
      ++stats_.packet_counter_gaps;
      stats_.missing_packets += step.missing;
    }
  }
  if (!fill_imu_sample(message_, 1.0 / options_.imu_rate_hz, sample_)) {
    ++stats_.non_imu_messages;
    return;
  }
  if (drop_next_) {
    drop_next_ = false;
    ++stats_.stale_samples_dropped;
    return;
  }
  double t_s = 0;
  if (!time_sample(frame_start_s, t_s)) return;
  sample_.t_s = t_s + options_.imu_time_offset_s;
  count_saturation(sample_);
  ++stats_.imu_samples;
  if (observer_)
    observer_(sample_, message_, message_.sample_time_fine ? std::optional<std::int64_t>(last_ticks_) : std::nullopt);
  out.push_back(sample_);
}

bool MtiStream::time_sample(const double* frame_start_s, double& t_s) {
  if (!message_.sample_time_fine) {
    ++stats_.samples_without_sample_time;
    if (frame_start_s == nullptr) return false;
    t_s = *frame_start_s;
    return true;
  }
  std::int64_t ticks = unwrapper_.unwrap(*message_.sample_time_fine);
  if (have_last_) {
    const double step_s = static_cast<double>(ticks - last_ticks_) / kSampleTimeFineHz;
    const bool jumped_back = step_s < -options_.restart_threshold_s;
    const bool ran_ahead = frame_start_s != nullptr &&
                           step_s > (*frame_start_s - last_frame_start_s_) + options_.restart_threshold_s;
    if (jumped_back || ran_ahead) {
      ++stats_.sensor_clock_restarts;
      unwrapper_.reset();
      mapper_.reset();
      ticks = unwrapper_.unwrap(*message_.sample_time_fine);
    } else if (step_s <= 0) {
      ++stats_.sample_time_backwards;
      return false;
    } else if (step_s > 1.5 / options_.imu_rate_hz) {
      ++stats_.sample_time_gaps;
    }
  }
  have_last_ = true;
  last_ticks_ = ticks;
  const double sensor_s = static_cast<double>(ticks) / kSampleTimeFineHz;
  if (frame_start_s == nullptr) {
    t_s = options_.epoch_s + sensor_s;
    return true;
  }
  last_frame_start_s_ = *frame_start_s;
  mapper_.observe(sensor_s, *frame_start_s);
  t_s = mapper_.host_time(sensor_s);
  return true;
}

void MtiStream::count_saturation(const ImuSample& s) {
  bool any = false;
  for (int axis = 0; axis < 3; ++axis) {
    stats_.accel_saturated[axis] += s.accel_saturated[axis];
    stats_.gyro_saturated[axis] += s.gyro_saturated[axis];
    any = any || s.accel_saturated[axis] || s.gyro_saturated[axis];
  }
  stats_.clipped_samples += any;
}

}  // namespace tumble::mti
