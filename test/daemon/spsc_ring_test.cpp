#include "daemon/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <vector>

#include "core/types.hpp"
#include "test/daemon/alloc_counter.hpp"

namespace tumble::daemon {
namespace {

std::vector<int> drain(SpscRing<int>& ring) {
  std::vector<int> out;
  int value = 0;
  while (ring.pop(value)) out.push_back(value);
  return out;
}

TEST(SpscRing, PopsInPushOrder) {
  SpscRing<int> ring(4);
  EXPECT_TRUE(ring.empty());
  int value = -1;
  EXPECT_FALSE(ring.pop(value));
  ring.push(1);
  ring.push(2);
  ring.push(3);
  EXPECT_EQ(ring.size(), 3u);
  EXPECT_EQ(drain(ring), (std::vector<int>{1, 2, 3}));
  EXPECT_TRUE(ring.empty());
  EXPECT_EQ(ring.dropped(), 0u);
}

TEST(SpscRing, FullRingDropsTheOldestAndCountsIt) {
  SpscRing<int> ring(3);
  for (int i = 1; i <= 3; ++i) ring.push(i);
  EXPECT_EQ(ring.size(), 3u);
  EXPECT_DOUBLE_EQ(ring.fill(), 1.0);
  EXPECT_TRUE(ring.full());
  ring.push(4);
  ring.push(5);
  EXPECT_EQ(ring.dropped(), 2u);
  EXPECT_EQ(ring.pushed(), 5u);
  EXPECT_EQ(ring.size(), 3u);
  EXPECT_EQ(drain(ring), (std::vector<int>{3, 4, 5}));
}

TEST(SpscRing, ManyLapsAheadOfTheConsumerKeepTheNewest) {
  SpscRing<int> ring(4);
  ring.push(0);
  int value = -1;
  ASSERT_TRUE(ring.pop(value));
  for (int i = 1; i <= 100; ++i) ring.push(i);
  EXPECT_EQ(ring.dropped(), 96u);
  EXPECT_EQ(drain(ring), (std::vector<int>{97, 98, 99, 100}));
  ring.push(101);  // and it keeps working after the catch-up
  EXPECT_EQ(drain(ring), (std::vector<int>{101}));
  const std::uint64_t popped = 1 + 4 + 1;
  EXPECT_EQ(popped + ring.dropped(), ring.pushed());
}

TEST(SpscRing, FillLevelFollowsPushesAndPops) {
  SpscRing<int> ring(4);
  ring.push(1);
  EXPECT_DOUBLE_EQ(ring.fill(), 0.25);
  ring.push(2);
  EXPECT_DOUBLE_EQ(ring.fill(), 0.5);
  int value = 0;
  ring.pop(value);
  EXPECT_EQ(ring.size(), 1u);
  ring.pop(value);
  EXPECT_EQ(ring.size(), 0u);
}

TEST(SpscRing, TryPushRefusesInsteadOfDropping) {
  SpscRing<int> ring(2);
  EXPECT_TRUE(ring.try_push(1));
  EXPECT_TRUE(ring.try_push(2));
  EXPECT_FALSE(ring.try_push(3));
  EXPECT_EQ(ring.dropped(), 0u);
  int value = 0;
  ASSERT_TRUE(ring.pop(value));
  EXPECT_TRUE(ring.try_push(3));
  EXPECT_EQ(drain(ring), (std::vector<int>{2, 3}));
}

TEST(SpscRing, PushIfPublishesOnlyAcceptedItems) {
  SpscRing<int> ring(4);
  EXPECT_FALSE(ring.push_if([](int& slot) {
    slot = 7;
    return false;
  }));
  EXPECT_TRUE(ring.push_if([](int& slot) {
    slot = 8;
    return true;
  }));
  EXPECT_EQ(ring.pushed(), 1u);
  EXPECT_EQ(drain(ring), (std::vector<int>{8}));
}

TEST(SpscRing, CapacityOneStillDropsOldest) {
  SpscRing<int> ring(1);
  ring.push(1);
  ring.push(2);
  EXPECT_EQ(ring.dropped(), 1u);
  EXPECT_EQ(drain(ring), (std::vector<int>{2}));
}

TEST(SpscRing, RejectsCapacitiesItCannotIndex) {
  EXPECT_THROW(SpscRing<int>(0), std::invalid_argument);
  EXPECT_THROW(SpscRing<int>(SpscRing<int>::kMaxCapacity + 1), std::invalid_argument);
}

TEST(SpscRing, CarriesEigenTypes) {
  SpscRing<ImuSample> ring(2);
  ImuSample sample;
  sample.t_s = 1.5;
  sample.gyro_rad_s = Eigen::Vector3d(1, 2, 3);
  sample.gyro_saturated = {false, true, false};
  ring.push(sample);
  ImuSample out;
  ASSERT_TRUE(ring.pop(out));
  EXPECT_EQ(out.t_s, 1.5);
  EXPECT_EQ(out.gyro_rad_s, Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(out.gyro_saturated[1]);
}

TEST(SpscRing, PushAndPopDoNotAllocate) {
  SpscRing<ImuSample> ring(8);
  ImuSample sample;
  ImuSample out;
  test::AllocationCounter allocations;
  for (int i = 0; i < 100; ++i) {  // wraps and drops many times
    sample.t_s = i;
    ring.push(sample);
    if (i % 3 == 0) ring.pop(out);
  }
  ring.try_push(sample);
  ring.push_if([](ImuSample& slot) { return slot.t_s >= 0.0; });
  while (ring.pop(out)) {
  }
  EXPECT_EQ(allocations.count(), 0u);
  EXPECT_GT(ring.dropped(), 0u);
}

TEST(AllocationCounter, SeesAllocationsOfThisThread) {
  test::AllocationCounter allocations;
  auto owned = std::make_unique<std::vector<int>>(100);
  EXPECT_EQ(allocations.count(), 2u);  // the vector object and its storage
  allocations.reset();
  EXPECT_EQ(allocations.count(), 0u);
}

}  // namespace
}  // namespace tumble::daemon
