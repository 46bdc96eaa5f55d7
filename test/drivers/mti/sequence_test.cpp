#include "drivers/mti/sequence.hpp"

#include <gtest/gtest.h>

namespace tumble::mti {
namespace {

TEST(SampleTimeUnwrapper, ContinuesAcrossTheDailyWrap) {
  SampleTimeUnwrapper u;
  EXPECT_EQ(u.unwrap(863'999'900), 863'999'900);
  EXPECT_EQ(u.unwrap(0), 864'000'000);
  EXPECT_EQ(u.unwrap(100), 864'000'100);
  EXPECT_EQ(u.unwrap(863'999'950), 863'999'950);  // an older time, the short way back
  EXPECT_EQ(u.unwrap(200), 864'000'200);
  u.reset();
  EXPECT_EQ(u.unwrap(5), 5);
}

TEST(SampleTimeUnwrapper, TwoWrapsAddTwoDays) {
  SampleTimeUnwrapper u;
  std::int64_t t = 0;
  for (std::int64_t raw = 0; raw < 2 * kSampleTimeFineWrap + 1000; raw += 100'000'000)
    t = u.unwrap(static_cast<std::uint32_t>(raw % kSampleTimeFineWrap));
  EXPECT_EQ(t, 1'700'000'000);  // 17 steps of 1e8 ticks, two of them across the wrap
}

std::uint32_t missing(PacketCounterTracker& t, std::uint16_t counter) {
  const CounterStep step = t.observe(counter);
  EXPECT_EQ(step.order, CounterOrder::InSequence) << counter;
  return step.missing;
}

TEST(PacketCounterTracker, CountsMissingPacketsAcrossTheWrap) {
  PacketCounterTracker t;
  EXPECT_EQ(missing(t, 65534), 0u);
  EXPECT_EQ(missing(t, 65535), 0u);
  EXPECT_EQ(missing(t, 0), 0u);
  EXPECT_EQ(missing(t, 3), 2u);
  EXPECT_EQ(missing(t, 65439), 65435u);  // 100 behind: a break, not a late frame
  EXPECT_EQ(missing(t, 1), 97u);
  t.reset();
  EXPECT_EQ(missing(t, 100), 0u);
}

TEST(PacketCounterTracker, ARepeatedOrSlightlyOlderCounterKeepsTheNewestAsReference) {
  PacketCounterTracker t;
  EXPECT_EQ(missing(t, 65535), 0u);
  EXPECT_EQ(t.observe(65535).order, CounterOrder::Repeated);
  EXPECT_EQ(missing(t, 2), 2u);
  EXPECT_EQ(t.observe(0).order, CounterOrder::Older);  // behind across the wrap
  EXPECT_EQ(t.observe(65535).order, CounterOrder::Older);
  EXPECT_EQ(t.observe(2).order, CounterOrder::Repeated);
  EXPECT_EQ(missing(t, 3), 0u);  // no gap for the late ones
  EXPECT_EQ(t.observe(static_cast<std::uint16_t>(3 - PacketCounterTracker::kMaxReorder)).order, CounterOrder::Older);
  EXPECT_EQ(missing(t, static_cast<std::uint16_t>(3 - PacketCounterTracker::kMaxReorder - 1)),
            65536u - PacketCounterTracker::kMaxReorder - 2);
}

TEST(PacketCounterTracker, ARestartIsABreakHoweverNearTheCounter) {
  PacketCounterTracker t;
  EXPECT_EQ(missing(t, 49), 0u);
  const CounterStep step = t.observe(0, true);  // the device started counting again
  EXPECT_EQ(step.order, CounterOrder::InSequence);
  EXPECT_EQ(missing(t, 1), 0u);
}

TEST(SampleTimeUnwrapper, StepToLooksAheadWithoutMoving) {
  SampleTimeUnwrapper u;
  EXPECT_EQ(u.step_to(500), 0);
  u.unwrap(kSampleTimeFineWrap - 10);
  EXPECT_EQ(u.step_to(5), 15);
  EXPECT_EQ(u.step_to(kSampleTimeFineWrap - 30), -20);
  EXPECT_EQ(u.unwrap(5), kSampleTimeFineWrap + 5);
}

}  // namespace
}  // namespace tumble::mti
