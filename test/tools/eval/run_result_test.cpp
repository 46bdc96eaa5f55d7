#include "tools/eval/run_result.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test/tools/eval/eval_test_support.hpp"
#include "tools/eval/tum_file.hpp"

namespace tumble::eval {
namespace {

using test::TempDir;
using test::write_file;

constexpr double kT0 = 1622032620.0;

// A run folder with a 10 s, 1 m/s straight ground truth, and tumbled's
// outputs for it: an estimate at 10 Hz with the given scale error, ending at end_s.
struct RunFixture {
  TempDir dir{"result"};
  BenchRun run;
  JobPaths paths;
  Variant variant{"GVTW", true};
  ChildOutcome clean_exit;

  RunFixture() {
    run = BenchRun{"cage-07", "cage", 10.0, dir.path() / "cage-07"};
    PoseSeries truth;
    for (int i = 0; i <= 10000; ++i) truth.push_back(TimedPose{kT0 + i * 1e-3, {i * 1e-3, 0.0, 0.0}});
    std::filesystem::create_directories(run.dir);
    write_tum(run.dir / "ground_truth.tum", truth);
    paths = job_paths(dir.path() / "eval", run.name, variant);
    std::filesystem::create_directories(paths.trajectory.parent_path());
    clean_exit.exit_code = 0;
    clean_exit.wall_s = 2.5;
    clean_exit.peak_rss_kib = 80 * 1024;
  }

  void write_estimate(double scale, double end_s) {
    PoseSeries estimate;
    for (double t = 0.05; t <= end_s + 1e-9; t += 0.1) estimate.push_back(TimedPose{kT0 + t, {scale * t, 0.0, 0.0}});
    write_tum(paths.trajectory, estimate);
    write_scan_log(9.95);
  }

  // Three scans, the middle one not placed, the last at last_scan_s.
  void write_scan_log(double last_scan_s) {
    write_file(paths.scan_log, "scan_index,t_s,registered,total_ms\n0," + std::to_string(kT0 + 0.05) + ",1,5\n1," +
                                   std::to_string(kT0 + 0.15) + ",0,6\n2," + std::to_string(kT0 + last_scan_s) +
                                   ",1,5\n");
  }

  RunResult evaluate(const ChildOutcome& child) const {
    return evaluate_job(run, variant, paths, child, EvalOptions{});
  }
};

TEST(RunResult, AGoodEstimateIsOkWithItsFigures) {
  RunFixture fixture;
  fixture.write_estimate(1.02, 9.95);
  const RunResult result = fixture.evaluate(fixture.clean_exit);
  EXPECT_EQ(result.status, RunStatus::Ok) << result.message;
  EXPECT_EQ(result.message, "");
  ASSERT_TRUE(result.drift.has_value());
  EXPECT_NEAR(result.drift->translation_cm_per_m, 2.0, 1e-3);
  EXPECT_EQ(result.scans, 3u);
  EXPECT_EQ(result.registered_scans, 2u);
  EXPECT_DOUBLE_EQ(result.realtime_multiple(), 4.0);
  EXPECT_EQ(result.trajectory, fixture.paths.trajectory);
  EXPECT_FALSE(result.runaway.has_value());  // a scan log without good_scan
}

TEST(RunResult, TheRunawayIsMeasuredWhereTheScanLogHasTheVerdict) {
  RunFixture fixture;
  fixture.write_estimate(1.02, 9.95);  // 2 cm off per metre, published as good throughout
  write_file(fixture.paths.scan_log, "scan_index,t_s,registered,good_scan,total_ms\n0," + std::to_string(kT0 + 0.05) +
                                         ",1,1,5\n1," + std::to_string(kT0 + 5.05) + ",1,1,6\n2," +
                                         std::to_string(kT0 + 9.95) + ",1,1,5\n");
  const RunResult result = fixture.evaluate(fixture.clean_exit);
  EXPECT_EQ(result.status, RunStatus::Ok) << result.message;
  ASSERT_TRUE(result.runaway.has_value());
  EXPECT_NEAR(result.runaway->growth_m(), 0.02 * 9.9, 1e-5);
}

TEST(RunResult, LostTrackingLargeErrorOrNoPosesIsDiverged) {
  RunFixture fixture;
  fixture.write_estimate(1.0, 5.05);
  RunResult result = fixture.evaluate(fixture.clean_exit);
  EXPECT_EQ(result.status, RunStatus::Diverged);
  EXPECT_TRUE(result.message.starts_with("registration stopped 4.9") ||
              result.message.starts_with("registration stopped 5.0"))
      << result.message;
  EXPECT_TRUE(result.message.ends_with(" s before the end of the run")) << result.message;

  fixture.write_estimate(3.0, 9.95);
  result = fixture.evaluate(fixture.clean_exit);
  EXPECT_EQ(result.status, RunStatus::Diverged);
  EXPECT_EQ(result.message, "translation error 200.0 cm/m > 100.0");

  fixture.write_estimate(1.0, 0.05);
  result = fixture.evaluate(fixture.clean_exit);
  EXPECT_EQ(result.status, RunStatus::Diverged);
  EXPECT_EQ(result.message, "1 estimated pose(s) inside the ground truth's time span (need 2)");
}

TEST(RunResult, ARecordingThatEndsEarlyIsBadInputNotDivergence) {
  RunFixture fixture;
  fixture.write_estimate(1.0, 5.05);
  fixture.write_scan_log(5.05);
  RunResult result = fixture.evaluate(fixture.clean_exit);
  EXPECT_EQ(result.status, RunStatus::Failed);
  EXPECT_TRUE(result.message.starts_with("tumbled's last scan is ")) << result.message;
  EXPECT_NE(result.message.find(" s before the ground truth ends (short or corrupt recording? see " +
                                fixture.paths.log.string() + ")"),
            std::string::npos)
      << result.message;

  write_file(fixture.paths.scan_log, "scan_index,t_s,registered,total_ms\n");
  result = fixture.evaluate(fixture.clean_exit);
  EXPECT_EQ(result.status, RunStatus::Failed);
  EXPECT_TRUE(result.message.starts_with("tumbled processed no scan")) << result.message;
}

TEST(RunResult, TumbledErrorsAndBadFilesFailTheRunWithTheReason) {
  RunFixture fixture;
  write_file(fixture.paths.log, "starting\ntumbled: --model: 'XX' is not one of NM|TW|VTW|GVTW|SAW\n\n");
  ChildOutcome usage_error = fixture.clean_exit;
  usage_error.exit_code = 2;
  RunResult result = fixture.evaluate(usage_error);
  EXPECT_EQ(result.status, RunStatus::Failed);
  EXPECT_EQ(result.message, "tumbled: exit code 2: tumbled: --model: 'XX' is not one of NM|TW|VTW|GVTW|SAW");

  result = fixture.evaluate(fixture.clean_exit);  // exit 0 but no trajectory written
  EXPECT_EQ(result.status, RunStatus::Failed);
  EXPECT_EQ(result.message, "trajectory: " + fixture.paths.trajectory.string() + ": cannot open");

  fixture.write_estimate(1.0, 9.95);
  write_file(fixture.run.dir / "ground_truth.tum", "1 2 3\n");
  result = fixture.evaluate(fixture.clean_exit);
  EXPECT_EQ(result.status, RunStatus::Failed);
  EXPECT_EQ(result.message, "ground truth: " + (fixture.run.dir / "ground_truth.tum").string() +
                                ":1: expected 8 numbers (t x y z qx qy qz qw), got 3 fields");
}

TEST(RunResult, ABadScanLogIsNotedButTheRunIsStillJudged) {
  RunFixture fixture;
  fixture.write_estimate(1.0, 9.95);
  write_file(fixture.paths.scan_log, "scan_index,t_s,total_ms\n0,5,5\n");
  const RunResult result = fixture.evaluate(fixture.clean_exit);
  EXPECT_EQ(result.status, RunStatus::Ok);
  EXPECT_EQ(result.message, "scan log unusable: scan log has no column 'registered'");
}

TEST(RunResult, NotStartedHasNoRealTimeFigure) {
  const RunResult result =
      failed_before_start(BenchRun{"cage-01", "cage", 9.0, "/nowhere"}, Variant{"NM", false}, "run folder missing");
  EXPECT_EQ(result.status, RunStatus::Failed);
  EXPECT_TRUE(std::isnan(result.realtime_multiple()));
  EXPECT_EQ(std::string(to_string(result.status)), "failed");
}

}  // namespace
}  // namespace tumble::eval
