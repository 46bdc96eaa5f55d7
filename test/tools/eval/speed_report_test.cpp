#include "tools/eval/speed_report.hpp"

#include <gtest/gtest.h>

#include "test/tools/eval/eval_test_support.hpp"

namespace tumble::eval {
namespace {

using test::TempDir;
using test::write_file;

RunResult ran(const std::string& run, double duration_s, double wall_s, long rss_kib, int exit_code = 0) {
  RunResult result;
  result.run = run;
  result.duration_s = duration_s;
  result.variant = Variant{"GVTW", true};
  result.child.exit_code = exit_code;
  result.child.wall_s = wall_s;
  result.child.peak_rss_kib = rss_kib;
  result.message = exit_code == 0 ? "" : "tumbled: exit code 1";
  return result;
}

TEST(SpeedReport, PoolsEveryScanOfEveryCleanRun) {
  const TempDir dir("speed");
  // Run a: voxel 1..100 ms-ish values; run b adds one slow scan.
  std::string a = "scan_index,downsample_ms,matching_ms,total_ms,latency_ms\n";
  for (int i = 1; i <= 99; ++i) a += std::to_string(i) + ",1,2,3," + std::to_string(i) + "\n";
  write_file(dir.path() / "a.csv", a);
  write_file(dir.path() / "b.csv", "scan_index,downsample_ms,matching_ms,total_ms,latency_ms\n0,1,50,51,100\n");
  const SpeedSummary summary =
      summarize_speed({ran("a", 10.0, 2.0, 90 * 1024), ran("b", 5.0, 2.0, 120 * 1024), ran("c", 5.0, 1.0, 10, 1)},
                      {dir.path() / "a.csv", dir.path() / "b.csv", dir.path() / "c.csv"});
  EXPECT_EQ(summary.runs, 2u);
  EXPECT_EQ(summary.failed_runs, 1u);
  ASSERT_EQ(summary.stages.size(), 2u);
  EXPECT_EQ(summary.stages[0].name, "downsample");
  EXPECT_EQ(summary.stages[1].name, "matching");
  EXPECT_EQ(summary.stages[1].scans, 100u);
  EXPECT_DOUBLE_EQ(summary.stages[1].p50_ms, 2.0);
  EXPECT_DOUBLE_EQ(summary.stages[1].max_ms, 50.0);
  EXPECT_DOUBLE_EQ(summary.stages[1].mean_ms, (99 * 2.0 + 50.0) / 100.0);
  ASSERT_TRUE(summary.total.has_value());
  EXPECT_NEAR(summary.total->p99_ms, 3.0 + 0.01 * 48.0, 1e-9);  // type 7: h = 98.01
  ASSERT_TRUE(summary.latency.has_value());
  EXPECT_DOUBLE_EQ(summary.latency->p50_ms, 50.5);
  EXPECT_DOUBLE_EQ(summary.replayed_s, 15.0);
  EXPECT_DOUBLE_EQ(summary.slowest_realtime_multiple, 2.5);
  EXPECT_DOUBLE_EQ(summary.peak_rss_mib, 120.0);
  ASSERT_EQ(summary.problems.size(), 1u);
  EXPECT_EQ(summary.problems[0], "c GVTW-deskew: tumbled: exit code 1");

  const std::string md = speed_markdown(summary, "heading");
  EXPECT_NE(md.find("| matching | 2.480 | 2.000 |"), std::string::npos) << md;
  EXPECT_NE(md.find("3.75× real time overall, slowest run 2.50×"), std::string::npos) << md;
}

TEST(SpeedReport, AnUnreadableScanLogLeavesTheRunOut) {
  const TempDir dir("speed");
  const SpeedSummary summary = summarize_speed({ran("a", 10.0, 2.0, 1024)}, {dir.path() / "absent.csv"});
  EXPECT_EQ(summary.runs, 0u);
  EXPECT_EQ(summary.failed_runs, 1u);
  EXPECT_FALSE(summary.total.has_value());
  EXPECT_EQ(summary.problems[0], "a GVTW-deskew: " + (dir.path() / "absent.csv").string() + ": cannot open");
}

}  // namespace
}  // namespace tumble::eval
