#include "tools/eval/run_score.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "test/tools/eval/eval_test_support.hpp"

namespace tumble::eval {
namespace {

using test::TempDir;
using test::write_file;

// Ground truth along x at 1 m/s for 10 s; the estimate is 5 cm short at the end.
std::string line_tum(double end_shortfall_m, int samples) {
  std::string tum = "# t x y z qx qy qz qw\n";
  for (int i = 0; i <= samples; ++i) {
    const double t = 10.0 * i / samples;
    const double x = t - end_shortfall_m * t / 10.0;
    tum += std::to_string(100.0 + t) + " " + std::to_string(x) + " 0 0 0 0 0 1\n";
  }
  return tum;
}

TEST(RunScore, DriftAndStageTimesOfOneRun) {
  const TempDir dir("score");
  write_file(dir.path() / "gt.tum", line_tum(0.0, 1000));
  write_file(dir.path() / "est.tum", line_tum(0.05, 100));
  write_file(dir.path() / "scans.csv",
             "scan_index,registered,converged,normals_ms,icp_ms,total_ms,latency_ms\n"
             "0,true,true,10,5,15,16\n1,true,false,20,7,27,28\n2,false,false,30,9,39,40\n");
  const RunScore score = score_run(dir.path() / "gt.tum", dir.path() / "est.tum", dir.path() / "scans.csv", {});
  EXPECT_NEAR(score.drift.distance_m, 10.0, 1e-6);
  EXPECT_NEAR(score.drift.translation_cm_per_m, 0.5, 1e-3);
  EXPECT_NEAR(score.drift.rotation_deg_per_m, 0.0, 1e-6);
  EXPECT_EQ(score.scans, 3u);
  EXPECT_EQ(score.registered, 2u);
  EXPECT_EQ(score.converged, 1u);
  ASSERT_EQ(score.stages.size(), 2u);
  EXPECT_EQ(score.stages[0].name, "normals");
  EXPECT_DOUBLE_EQ(score.stages[0].p50_ms, 20.0);
  EXPECT_DOUBLE_EQ(score.stages[1].max_ms, 9.0);
  ASSERT_TRUE(score.total.has_value());
  EXPECT_DOUBLE_EQ(score.total->p50_ms, 27.0);

  const std::string md = score_markdown(score);
  EXPECT_NE(md.find("**0.50 cm/m**"), std::string::npos) << md;
  EXPECT_NE(md.find("Scans: 3, registered 2, ICP converged 1."), std::string::npos) << md;
  EXPECT_NE(md.find("| normals | 20.000 | 20.000 |"), std::string::npos) << md;
  EXPECT_FALSE(score.runaway.has_value());
  EXPECT_NE(md.find("\nRunaway: not measured (the scan log has no good_scan column).\n"), std::string::npos) << md;
}

TEST(RunScore, TheRunawayFromTheScanLogsVerdicts) {
  const TempDir dir("score");
  write_file(dir.path() / "gt.tum", line_tum(0.0, 1000));
  write_file(dir.path() / "est.tum", line_tum(0.05, 100));  // the error grows 5 mm per second
  write_file(dir.path() / "scans.csv",
             "t_s,registered,converged,good_scan,total_ms,latency_ms\n"
             "100.0,1,1,1,5,6\n102.0,1,1,1,5,6\n106.0,1,1,0,5,6\n110.0,1,1,1,5,6\n");
  const RunScore score = score_run(dir.path() / "gt.tum", dir.path() / "est.tum", dir.path() / "scans.csv", {});
  ASSERT_TRUE(score.runaway.has_value());
  EXPECT_NEAR(score.runaway->growth_m(), 0.01, 1e-6);
  const std::string md = score_markdown(score);
  EXPECT_NE(md.find("\nRunaway, the largest rise of the position error within a stretch of consecutive good scans "
                    "(none may exceed 0.5 m; times since the first pose):\n"
                    "- 0.010 m over 0.0–2.0 s (2 scans); stretches over 0.5 m: 0; scans not good: 25.00 % of 4\n"),
            std::string::npos)
      << md;
}

TEST(RunScore, WithoutAScanLogOnlyTheDriftIsReported) {
  const TempDir dir("score");
  write_file(dir.path() / "gt.tum", line_tum(0.0, 1000));
  write_file(dir.path() / "est.tum", line_tum(0.1, 100));
  const RunScore score = score_run(dir.path() / "gt.tum", dir.path() / "est.tum", std::nullopt, {});
  EXPECT_NEAR(score.drift.translation_cm_per_m, 1.0, 1e-3);
  EXPECT_FALSE(score.total.has_value());
  EXPECT_EQ(score_markdown(score).find("Scans:"), std::string::npos);
}

TEST(RunScore, AMissingTrajectoryNamesTheFile) {
  const TempDir dir("score");
  write_file(dir.path() / "gt.tum", line_tum(0.0, 1000));
  try {
    score_run(dir.path() / "gt.tum", dir.path() / "absent.tum", std::nullopt, {});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("absent.tum"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tumble::eval
