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

TEST(PacketCounterTracker, CountsMissingPacketsAcrossTheWrap) {
  PacketCounterTracker t;
  EXPECT_EQ(t.observe(65534), 0u);
  EXPECT_EQ(t.observe(65535), 0u);
  EXPECT_EQ(t.observe(0), 0u);
  EXPECT_EQ(t.observe(3), 2u);
  EXPECT_EQ(t.observe(3), 0u);  // repeated, not a gap
  EXPECT_EQ(t.observe(65533), 65529u);
  EXPECT_EQ(t.observe(1), 3u);
  t.reset();
  EXPECT_EQ(t.observe(100), 0u);
}

}  // namespace
}  // namespace tumble::mti
