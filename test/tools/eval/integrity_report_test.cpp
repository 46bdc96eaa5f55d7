#include "tools/eval/integrity_report.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>

namespace tumble::eval {
namespace {

// Ground truth along x at 1 m/s, sampled at 1 kHz for 10 s.
PoseSeries straight_line() {
  PoseSeries truth;
  for (int i = 0; i <= 10000; ++i) {
    TimedPose p;
    p.t_s = i * 1e-3;
    p.position_m = Eigen::Vector3d(p.t_s, 0, 0);
    truth.push_back(p);
  }
  return truth;
}

// One scan every 0.1 s from 0.1 s, the first starting the map; position
// sigma 1 cm on each axis; expected error 1 cm.
ScanLog scan_log(std::size_t scans) {
  ScanLog log;
  log.columns = {"t_s", "registered", "iterations", "expected_error_m", "cov_txx", "cov_tyy", "cov_tzz",
                 "cov_txy", "cov_txz", "cov_tyz"};
  log.values.assign(log.columns.size(), std::vector<double>(scans, 0.0));
  for (std::size_t i = 0; i < scans; ++i) {
    log.values[0][i] = 0.1 * static_cast<double>(i + 1);
    log.values[1][i] = 1.0;
    log.values[2][i] = i == 0 ? 0.0 : 3.0;
    log.values[3][i] = 0.01;
    for (std::size_t c = 4; c < 7; ++c) log.values[c][i] = 1e-4;
  }
  return log;
}

PoseSeries estimate_at_scans(const ScanLog& log, std::size_t displaced_scan, double displacement_m) {
  PoseSeries estimate;
  for (std::size_t i = 0; i < log.scans(); ++i) {
    TimedPose p;
    p.t_s = log.values[0][i];
    p.position_m = Eigen::Vector3d(p.t_s + (i == displaced_scan ? displacement_m : 0.0), 0, 0);
    estimate.push_back(p);
  }
  return estimate;
}

TEST(IntegrityReport, OneDisplacedPoseIsTwoIncrementErrorsAndItsNeesFollowsTheCovariance) {
  const ScanLog log = scan_log(50);
  const std::vector<ScanIntegrity> scans = score_scans(straight_line(), estimate_at_scans(log, 20, 0.1), log, 10);
  ASSERT_EQ(scans.size(), 49u);  // the map's first scan has no increment
  const ScanIntegrity& displaced = scans[19];
  EXPECT_NEAR(displaced.increment_error_m, 0.1, 1e-9);
  EXPECT_NEAR(displaced.window_error_m, 0.1, 1e-9);
  // e = 0.1 m along x, P_a + P_b = 2e-4 m²: 0.01 / 2e-4 / 3.
  EXPECT_NEAR(displaced.nees_per_dof, 0.01 / 2e-4 / 3.0, 1e-6);
  EXPECT_NEAR(scans[20].increment_error_m, 0.1, 1e-9);  // back on the line
  EXPECT_NEAR(scans[20].window_error_m, 0.0, 1e-9);
  EXPECT_NEAR(scans[5].increment_error_m, 0.0, 1e-9);
  EXPECT_TRUE(std::isnan(scans[5].window_error_m));  // fewer than 10 registered scans before it
}

TEST(IntegrityReport, AnUnregisteredScanBreaksTheIncrements) {
  ScanLog log = scan_log(30);
  log.values[1][15] = 0.0;
  const std::vector<ScanIntegrity> scans = score_scans(straight_line(), estimate_at_scans(log, 99, 0.0), log, 10);
  EXPECT_EQ(scans.size(), 27u);  // 29 increments, minus the unregistered scan's and the one after it
}

TEST(IntegrityReport, CountsFalseAlarmsOnGoodRunsAndMissedBadRuns) {
  RunIntegrity good{"good-run", 0.1, 10.0, std::vector<ScanIntegrity>(99, ScanIntegrity{0.01, 0.001, 0.01, 1.0, std::nullopt})};
  good.scans[40].expected_error_m = 0.05;
  // A run that ends well may still have slipped on the way (and come back):
  // a flag there is counted, and said to be on a slipped scan.
  good.scans[41] = ScanIntegrity{0.05, 0.2, 0.3, 1.0, std::nullopt};
  RunIntegrity bad{"bad-run", 3.0, 5.0, std::vector<ScanIntegrity>(10, ScanIntegrity{0.01, 0.3, 0.5, 9.0, std::nullopt})};
  const std::string md = integrity_markdown({good, bad}, {0.04, 0.06});
  EXPECT_NE(md.find("| 0.04 m | 2.02 % (2 of 99; 1) | 1 of 1 | 0 of 1 | 9.09 % | 1.02 % |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 0.06 m | 0.00 % (0 of 99; 0) | 0 of 1 | 0 of 1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("never flagged at 0.04 m: bad-run (3.00 cm/m over 5.00 m)"), std::string::npos) << md;
  EXPECT_NE(md.find("| under 0.5 cm/m | 99 | 1.00 | 1.00 |"), std::string::npos) << md;
}

TEST(IntegrityReport, ReadsTumbledsVerdictWhereTheLogHasIt) {
  ScanLog log = scan_log(20);
  const std::vector<ScanIntegrity> without = score_scans(straight_line(), estimate_at_scans(log, 99, 0.0), log, 10);
  ASSERT_EQ(without.size(), 19u);
  EXPECT_FALSE(without[3].good_scan.has_value());
  log.columns.push_back("good_scan");
  log.values.push_back(std::vector<double>(20, 1.0));
  log.values.back()[5] = 0.0;
  const std::vector<ScanIntegrity> with = score_scans(straight_line(), estimate_at_scans(log, 99, 0.0), log, 10);
  ASSERT_EQ(with.size(), 19u);
  EXPECT_EQ(with[3].good_scan, std::optional<bool>(true));
  EXPECT_EQ(with[4].good_scan, std::optional<bool>(false));  // scan 5: the increment from scan 4
}

TEST(IntegrityReport, ScoresTumbledsVerdictBesideTheThresholdsWhenEveryScanHasOne) {
  const ScanIntegrity fine{0.01, 0.001, 0.01, 1.0, true};
  RunIntegrity good{"good-run", 0.1, 10.0, std::vector<ScanIntegrity>(100, fine)};
  good.scans[10].good_scan = false;
  good.scans[11].good_scan = false;
  good.scans[12].good_scan = false;
  RunIntegrity bad{"bad-run", 3.0, 5.0, std::vector<ScanIntegrity>(10, fine)};
  bad.scans[7].good_scan = false;  // a clipped gyro, say: the expected error stays low
  RunIntegrity missed{"missed-run", 2.5, 4.0, std::vector<ScanIntegrity>(10, fine)};
  std::string md = integrity_markdown({good, bad, missed}, {0.04});
  EXPECT_NE(md.find("| 0.04 m | 0.00 % (0 of 100; 0) | 0 of 1 | 0 of 2 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| tumbled's verdict | 3.00 % (3 of 100; 0) | 1 of 1 | 1 of 2 |"), std::string::npos) << md;
  EXPECT_NE(md.find("never flagged by tumbled's verdict: missed-run (2.50 cm/m over 4.00 m)."), std::string::npos)
      << md;
  missed.scans[2].good_scan.reset();  // a log from before the verdict column
  md = integrity_markdown({good, bad, missed}, {0.04});
  EXPECT_EQ(md.find("tumbled's verdict"), std::string::npos) << md;
}

Runaway runaway_growing(double growth_m, std::size_t stretches_over) {
  Runaway runaway;
  runaway.scans = 100;
  runaway.stretches_over_limit = stretches_over;
  runaway.largest = GoodStretch{2.0, 9.5, 40, growth_m};
  return runaway;
}

TEST(IntegrityReport, NamesTheRunsWhosePoseRanAwayWhilePublishedAsGood) {
  const ScanIntegrity fine{0.01, 0.001, 0.01, 1.0, true};
  std::vector<RunIntegrity> runs(4, RunIntegrity{"", 0.1, 10.0, std::vector<ScanIntegrity>(10, fine)});
  runs[0].name = "steady";
  runs[0].runaway = runaway_growing(0.12, 0);
  runs[1].name = "away";
  runs[1].runaway = runaway_growing(1.5, 2);
  runs[2].name = "just-over";
  runs[2].runaway = runaway_growing(0.51, 1);
  runs[3].name = "old-log";  // no good_scan column: not measured
  const std::string md = integrity_markdown(runs, {0.04});
  EXPECT_NE(md.find("| 3 of 4 | 1.500 m over 2.0–9.5 s (40 scans) | away | 2 |\n"), std::string::npos) << md;
  EXPECT_NE(md.find("\nRuns over 0.5 m: away, 1.500 m over 2.0–9.5 s (40 scans), 2 stretch(es) over; just-over, "
                    "0.510 m over 2.0–9.5 s (40 scans), 1 stretch(es) over.\n"),
            std::string::npos)
      << md;

  runs.resize(1);
  const std::string calm = integrity_markdown(runs, {0.04});
  EXPECT_NE(calm.find("| 1 of 1 | 0.120 m over 2.0–9.5 s (40 scans) | steady | 0 |\n"), std::string::npos) << calm;
  EXPECT_EQ(calm.find("Runs over 0.5 m"), std::string::npos) << calm;
}

}  // namespace
}  // namespace tumble::eval
