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
  // The step unwrap() would take to sample_time_fine, without taking it (0 before the first).
  std::int64_t step_to(std::uint32_t sample_time_fine) const;
  void reset() { started_ = false; }

 private:
  bool started_ = false;
  std::int64_t last_raw_ = 0;
  std::int64_t last_unwrapped_ = 0;
};

// Where a PacketCounter stands against the newest one seen so far.
enum class CounterOrder : std::uint8_t {
  InSequence,  // the next one, the first one, or one after a break too large to be a reordering
  Repeated,    // the newest one again: a duplicated frame
  Older,       // at most kMaxReorder behind the newest: a frame that arrived late
};

struct CounterStep {
  CounterOrder order = CounterOrder::InSequence;
  std::uint32_t missing = 0;  // packets skipped before this one (InSequence only)
};

// Packets lost, repeated or reordered between PacketCounters.
class PacketCounterTracker {
 public:
  // Further back than this is not a late frame but a break (a device restart
  // starts again from 0): counted as skipped packets, and the new reference.
  static constexpr int kMaxReorder = 64;

  // A Repeated or Older counter leaves the newest one as the reference.
  // restart: the device started afresh (its sample clock says so), so the
  // counter is a break even when it is just behind the newest.
  CounterStep observe(std::uint16_t packet_counter, bool restart = false);
  void reset() { started_ = false; }

 private:
  bool started_ = false;
  std::uint16_t last_ = 0;
};

}  // namespace tumble::mti
