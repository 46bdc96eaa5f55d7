// The MTi's two counters and their wraps: SampleTimeFine (10 kHz ticks, one
// day = 864'000'000) and PacketCounter (16 bit, +1 per MTData2 of any kind).
#pragma once

#include <cstdint>

namespace tumble::mti {

inline constexpr std::int64_t kSampleTimeFineWrap = 864'000'000;
inline constexpr double kSampleTimeFineHz = 10'000.0;

// SampleTimeFine made continuous across its daily wrap. Steps are taken the
// short way round the wrap, so a step back (an older time) comes out negative.
class SampleTimeUnwrapper {
 public:
  std::int64_t unwrap(std::uint32_t sample_time_fine);
  void reset() { started_ = false; }

 private:
  bool started_ = false;
  std::int64_t last_raw_ = 0;
  std::int64_t last_unwrapped_ = 0;
};

// Packets lost between consecutive PacketCounters.
class PacketCounterTracker {
 public:
  // Returns how many packets are missing before this one (0 when in sequence,
  // also for the first packet and for a repeated counter).
  std::uint32_t observe(std::uint16_t packet_counter);
  void reset() { started_ = false; }

 private:
  bool started_ = false;
  std::uint16_t last_ = 0;
};

}  // namespace tumble::mti
