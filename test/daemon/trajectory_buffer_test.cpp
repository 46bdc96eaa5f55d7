#include "daemon/trajectory_buffer.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "test/daemon/alloc_counter.hpp"

namespace tumble::daemon {
namespace {

TrajectoryRecord sample_at(double t) {
  TrajectoryRecord r;
  r.t_s = t;
  r.p_w_m = {t, 2 * t, 3 * t};
  r.gyro_saturated_axes = 0b010;
  return r;
}

TEST(SeqlockRing, ReadsBackWhatWasPublished) {
  TrajectoryBuffer buffer(4);
  EXPECT_EQ(buffer.published(), 0u);
  TrajectoryRecord out;
  EXPECT_FALSE(buffer.read(0, out));
  buffer.publish(sample_at(1.0));
  buffer.publish(sample_at(2.0));
  EXPECT_EQ(buffer.published(), 2u);
  ASSERT_TRUE(buffer.read(1, out));
  EXPECT_EQ(out.t_s, 2.0);
  EXPECT_EQ(out.p_w_m[2], 6.0);
  EXPECT_EQ(out.gyro_saturated_axes, 0b010);
  EXPECT_FALSE(buffer.read(2, out));  // not published yet
}

TEST(SeqlockRing, OverwrittenItemsReadAsGone) {
  TrajectoryBuffer buffer(4);
  for (int i = 0; i < 6; ++i) buffer.publish(sample_at(i));
  TrajectoryRecord out;
  EXPECT_FALSE(buffer.read(0, out));
  EXPECT_FALSE(buffer.read(1, out));
  ASSERT_TRUE(buffer.read(2, out));
  EXPECT_EQ(out.t_s, 2.0);
}

TEST(ReadWindow, BracketsTheRequestedInterval) {
  TrajectoryBuffer buffer(64);
  for (int i = 0; i < 20; ++i) buffer.publish(sample_at(0.1 * i));
  std::vector<TrajectoryRecord> out(64);
  const WindowRead w = read_window(buffer, 0.55, 0.95, out);
  ASSERT_EQ(w.status, WindowStatus::Ok);
  ASSERT_EQ(w.count, 6u);  // 0.5 .. 1.0
  EXPECT_DOUBLE_EQ(out[0].t_s, 0.5);
  EXPECT_DOUBLE_EQ(out[5].t_s, 1.0);
  for (std::size_t i = 1; i < w.count; ++i) EXPECT_LT(out[i - 1].t_s, out[i].t_s);
}

TEST(ReadWindow, ARepublishedTailSupersedesWhatItRewrote) {
  TrajectoryBuffer buffer(64);
  for (int i = 0; i <= 10; ++i) buffer.publish(sample_at(0.1 * i));
  // A correction at 0.75 rewrote everything after it: a sample at 0.75
  // itself, then 0.8 .. 1.0 again, then new samples.
  TrajectoryRecord corrected = sample_at(0.75);
  corrected.p_w_m[1] = -1.0;
  buffer.publish(corrected);
  for (int i = 8; i <= 12; ++i) {
    TrajectoryRecord r = sample_at(0.1 * i);
    r.p_w_m[1] = -1.0;
    buffer.publish(r);
  }
  std::vector<TrajectoryRecord> out(64);
  const WindowRead w = read_window(buffer, 0.55, 1.05, out);
  ASSERT_EQ(w.status, WindowStatus::Ok);
  const std::vector<double> expected_t = {0.5, 0.6, 0.7, 0.75, 0.8, 0.9, 1.0, 1.1};
  ASSERT_EQ(w.count, expected_t.size());
  for (std::size_t i = 0; i < w.count; ++i) {
    EXPECT_DOUBLE_EQ(out[i].t_s, expected_t[i]);
    EXPECT_EQ(out[i].p_w_m[1] == -1.0, out[i].t_s >= 0.75) << "sample " << i;
  }
}

TEST(ReadWindow, ExactSampleTimesNeedNoExtraSamples) {
  TrajectoryBuffer buffer(64);
  for (int i = 0; i < 10; ++i) buffer.publish(sample_at(i));
  std::vector<TrajectoryRecord> out(64);
  const WindowRead w = read_window(buffer, 2.0, 4.0, out);
  ASSERT_EQ(w.status, WindowStatus::Ok);
  ASSERT_EQ(w.count, 3u);
  EXPECT_EQ(out[0].t_s, 2.0);
  EXPECT_EQ(out[2].t_s, 4.0);
}

TEST(ReadWindow, ReportsWhenTheTrajectoryHasNotReachedTheEnd) {
  TrajectoryBuffer buffer(64);
  std::vector<TrajectoryRecord> out(64);
  EXPECT_EQ(read_window(buffer, 0.0, 1.0, out).status, WindowStatus::NotYetReached);
  buffer.publish(sample_at(0.5));
  EXPECT_EQ(read_window(buffer, 0.0, 1.0, out).status, WindowStatus::NotYetReached);
}

TEST(ReadWindow, StartsAtTheFirstSampleWhenTheTrajectoryStartsLate) {
  TrajectoryBuffer buffer(64);
  for (int i = 5; i < 10; ++i) buffer.publish(sample_at(i));
  std::vector<TrajectoryRecord> out(64);
  const WindowRead w = read_window(buffer, 0.0, 7.0, out);
  ASSERT_EQ(w.status, WindowStatus::Ok);
  ASSERT_EQ(w.count, 3u);
  EXPECT_EQ(out[0].t_s, 5.0);
}

TEST(ReadWindow, ReportsOverwrittenSamplesAndSmallOutputs) {
  TrajectoryBuffer buffer(8);
  for (int i = 0; i < 20; ++i) buffer.publish(sample_at(i));
  std::vector<TrajectoryRecord> out(64);
  EXPECT_EQ(read_window(buffer, 2.0, 15.0, out).status, WindowStatus::Overwritten);
  std::vector<TrajectoryRecord> small(2);
  EXPECT_EQ(read_window(buffer, 14.0, 17.0, small).status, WindowStatus::TooSmall);
}

TEST(TrajectoryBuffer, PublishAndWindowReadsDoNotAllocate) {
  TrajectoryBuffer buffer(128);
  std::vector<TrajectoryRecord> out(128);
  test::AllocationCounter allocations;
  std::size_t total = 0;
  for (int i = 0; i < 1000; ++i) {
    buffer.publish(sample_at(0.01 * i));
    if (i > 20) total += read_window(buffer, 0.01 * (i - 10), 0.01 * i, out).count;
  }
  EXPECT_EQ(allocations.count(), 0u);
  EXPECT_GT(total, 0u);
}

}  // namespace
}  // namespace tumble::daemon
