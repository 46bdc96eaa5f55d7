#include "drivers/mti/sequence.hpp"

namespace tumble::mti {

std::int64_t SampleTimeUnwrapper::unwrap(std::uint32_t sample_time_fine) {
  const std::int64_t raw = sample_time_fine;
  if (!started_) {
    started_ = true;
    last_raw_ = raw;
    last_unwrapped_ = raw;
    return raw;
  }
  std::int64_t step = (raw - last_raw_) % kSampleTimeFineWrap;
  if (step > kSampleTimeFineWrap / 2) step -= kSampleTimeFineWrap;
  if (step <= -kSampleTimeFineWrap / 2) step += kSampleTimeFineWrap;
  last_raw_ = raw;
  last_unwrapped_ += step;
  return last_unwrapped_;
}

std::uint32_t PacketCounterTracker::observe(std::uint16_t packet_counter) {
  const bool first = !started_;
  const std::uint16_t last = last_;
  started_ = true;
  last_ = packet_counter;
  if (first || packet_counter == last) return 0;
  return static_cast<std::uint16_t>(packet_counter - last - 1);
}

}  // namespace tumble::mti
