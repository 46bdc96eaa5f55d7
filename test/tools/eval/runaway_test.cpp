#include "tools/eval/runaway.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace tumble::eval {
namespace {

// Scans every 0.1 s from 0, all good, with these position errors.
std::vector<ScanVerdict> good_scans_with_errors(const std::vector<double>& errors_m) {
  std::vector<ScanVerdict> scans;
  for (std::size_t i = 0; i < errors_m.size(); ++i)
    scans.push_back(ScanVerdict{0.1 * static_cast<double>(i), true, errors_m[i]});
  return scans;
}

TEST(Runaway, AGoodStretchThatRises60CmIsFlagged) {
  // Down to 0.1 m first: the rise counts from the stretch's lowest error, not its first.
  const Runaway runaway = find_runaway(good_scans_with_errors({0.2, 0.1, 0.3, 0.5, 0.7, 0.6}));
  ASSERT_TRUE(runaway.largest.has_value());
  EXPECT_NEAR(runaway.growth_m(), 0.6, 1e-12);
  EXPECT_DOUBLE_EQ(runaway.largest->start_s, 0.0);
  EXPECT_DOUBLE_EQ(runaway.largest->end_s, 0.5);
  EXPECT_EQ(runaway.largest->scans, 6u);
  EXPECT_EQ(runaway.stretches_over_limit, 1u);
  EXPECT_EQ(runaway.scans, 6u);
  EXPECT_EQ(runaway.not_good_scans, 0u);
  EXPECT_EQ(largest_growth_text(runaway), "0.600 m over 0.0–0.5 s (6 scans)");
}

TEST(Runaway, TheSameRiseSplitByOneScanNotGoodIsNotFlagged) {
  std::vector<ScanVerdict> scans = good_scans_with_errors({0.0, 0.1, 0.2, 0.3, 0.35, 0.4, 0.5, 0.6});
  scans[4].good = false;  // tumbled degraded the scan: the pose is not vouched for there
  const Runaway runaway = find_runaway(scans);
  EXPECT_NEAR(runaway.growth_m(), 0.3, 1e-12);  // 0.0 → 0.3, and 0.4 → 0.6 is 0.2
  EXPECT_DOUBLE_EQ(runaway.largest->end_s, 0.3);
  EXPECT_EQ(runaway.largest->scans, 4u);
  EXPECT_EQ(runaway.stretches_over_limit, 0u);
  EXPECT_EQ(runaway.not_good_scans, 1u);
}

TEST(Runaway, AScanWithoutAPoseNeitherEndsAStretchNorJoinsIt) {
  std::vector<ScanVerdict> scans = good_scans_with_errors({0.0, 0.2, 9.0, 0.4, 0.6});
  scans[2].position_error_m.reset();
  const Runaway runaway = find_runaway(scans);
  EXPECT_NEAR(runaway.growth_m(), 0.6, 1e-12);
  EXPECT_EQ(runaway.largest->scans, 4u);
  EXPECT_EQ(runaway.stretches_over_limit, 1u);
}

TEST(Runaway, AFallingErrorDoesNotGrow) {
  const Runaway runaway = find_runaway(good_scans_with_errors({1.5, 1.2, 0.8, 0.3}));
  ASSERT_TRUE(runaway.largest.has_value());
  EXPECT_DOUBLE_EQ(runaway.growth_m(), 0.0);
  EXPECT_EQ(runaway.stretches_over_limit, 0u);
}

TEST(Runaway, AnEmptyLogHasNoStretch) {
  ScanLog log;
  log.columns = {"t_s", "registered", "good_scan"};
  log.values.resize(3);
  const PoseSeries line = {TimedPose{0.0, {0, 0, 0}}, TimedPose{10.0, {10, 0, 0}}};
  const std::optional<Runaway> runaway = runaway_of(line, line, log);
  ASSERT_TRUE(runaway.has_value());
  EXPECT_EQ(runaway->scans, 0u);
  EXPECT_FALSE(runaway->largest.has_value());
  EXPECT_DOUBLE_EQ(runaway->growth_m(), 0.0);
  EXPECT_EQ(runaway->stretches_over_limit, 0u);
  EXPECT_EQ(largest_growth_text(*runaway), "0.000 m (no good scan with a pose)");
}

// Ground truth along x at 1 m/s from t = 100 s, sampled at 1 kHz for 10 s.
PoseSeries truth_along_x() {
  PoseSeries truth;
  for (int i = 0; i <= 10000; ++i) truth.push_back(TimedPose{100.0 + i * 1e-3, {i * 1e-3, 0.0, 0.0}});
  return truth;
}

// One scan every 0.5 s from 101 s, registered and good.
ScanLog runaway_scan_log(std::size_t scans) {
  ScanLog log;
  log.columns = {"t_s", "registered", "good_scan"};
  log.values.assign(3, std::vector<double>(scans, 1.0));
  for (std::size_t i = 0; i < scans; ++i) log.values[0][i] = 101.0 + 0.5 * static_cast<double>(i);
  return log;
}

TEST(Runaway, TheEstimateIsAlignedAtItsFirstPoseAsScoreDoes) {
  // The estimate lives in its own frame (turned 90° about z, elsewhere), and
  // from scan 4 on drifts sideways 0.2 m per scan in that frame.
  const ScanLog log = runaway_scan_log(10);
  const Eigen::Quaterniond frame(Eigen::AngleAxisd(std::numbers::pi / 2.0, Eigen::Vector3d::UnitZ()));
  PoseSeries estimate;
  for (std::size_t i = 0; i < log.scans(); ++i) {
    const double t_s = log.values[0][i];
    const double sideways_m = i >= 4 ? 0.2 * static_cast<double>(i - 3) : 0.0;
    estimate.push_back(TimedPose{t_s, frame * Eigen::Vector3d(t_s - 100.0, sideways_m, 0.0) + Eigen::Vector3d(5, 5, 1),
                                 frame});
  }
  const std::vector<ScanVerdict> verdicts = scan_verdicts(truth_along_x(), estimate, log);
  ASSERT_EQ(verdicts.size(), 10u);
  EXPECT_DOUBLE_EQ(verdicts[0].t_s, 0.0);  // since the first pose
  EXPECT_NEAR(*verdicts[3].position_error_m, 0.0, 1e-9);
  EXPECT_NEAR(*verdicts[9].position_error_m, 1.2, 1e-9);
  const Runaway runaway = find_runaway(verdicts);
  EXPECT_NEAR(runaway.growth_m(), 1.2, 1e-9);
  EXPECT_EQ(runaway.stretches_over_limit, 1u);

  ScanLog judged = log;
  judged.values[2][6] = 0.0;  // scan 6 (0.6 m off) not good: 0.0 → 0.4, then 0.8 → 1.2
  EXPECT_NEAR(runaway_of(truth_along_x(), estimate, judged)->growth_m(), 0.4, 1e-9);
  ScanLog unregistered = log;
  unregistered.values[1][6] = 0.0;  // not registered ends a stretch too, whatever good_scan says
  EXPECT_NEAR(runaway_of(truth_along_x(), estimate, unregistered)->growth_m(), 0.4, 1e-9);
}

TEST(Runaway, NotMeasuredWithoutTheVerdictColumn) {
  ScanLog log = runaway_scan_log(3);
  log.columns.pop_back();
  log.values.pop_back();
  EXPECT_FALSE(runaway_of(truth_along_x(), truth_along_x(), log).has_value());
}

}  // namespace
}  // namespace tumble::eval
