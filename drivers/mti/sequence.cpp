#include "drivers/mti/sequence.hpp"

namespace tumble::mti {

std::int64_t SampleTimeUnwrapper::step_to(std::uint32_t sample_time_fine) const {
  if (!started_) return 0;
  std::int64_t step = (static_cast<std::int64_t>(sample_time_fine) - last_raw_) % kSampleTimeFineWrap;
  if (step > kSampleTimeFineWrap / 2) step -= kSampleTimeFineWrap;
  if (step <= -kSampleTimeFineWrap / 2) step += kSampleTimeFineWrap;
  return step;
}

std::int64_t SampleTimeUnwrapper::unwrap(std::uint32_t sample_time_fine) {
  const std::int64_t raw = sample_time_fine;
  if (!started_) {
    started_ = true;
    last_raw_ = raw;
    last_unwrapped_ = raw;
    return raw;
  }
  last_unwrapped_ += step_to(sample_time_fine);
  last_raw_ = raw;
  return last_unwrapped_;
}

CounterStep PacketCounterTracker::observe(std::uint16_t packet_counter, bool restart) {
  if (started_ && !restart) {
    const auto behind = static_cast<std::uint16_t>(last_ - packet_counter);
    if (behind == 0) return {CounterOrder::Repeated, 0};
    if (behind <= kMaxReorder) return {CounterOrder::Older, 0};
  }
  const bool first = !started_;
  const std::uint16_t last = last_;
  started_ = true;
  last_ = packet_counter;
  if (first) return {};
  return {CounterOrder::InSequence, static_cast<std::uint16_t>(packet_counter - last - 1)};
}

}  // namespace tumble::mti
