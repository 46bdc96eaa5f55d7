#include "tools/eval/matrix_report.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "test/tools/eval/eval_test_support.hpp"

namespace tumble::eval {
namespace {

using test::read_file;
using test::TempDir;

RunResult result_of(const std::string& run, const Variant& variant, RunStatus status, double cm_per_m, double deg_per_m,
                    const std::string& message = "") {
  RunResult result;
  result.run = run;
  result.kind = "cage";
  result.duration_s = 10.0;
  result.variant = variant;
  result.status = status;
  result.message = message;
  result.child.exit_code = 0;
  result.child.wall_s = 4.0;
  result.child.peak_rss_kib = 2048;
  if (status != RunStatus::Failed) {
    DriftResult drift;
    drift.poses = 90;
    drift.distance_m = 5.0;
    drift.final_translation_error_m = cm_per_m * drift.distance_m / 100.0;
    drift.final_rotation_error_deg = deg_per_m * drift.distance_m;
    drift.translation_cm_per_m = cm_per_m;
    drift.rotation_deg_per_m = deg_per_m;
    drift.rpe_segments = 40;
    drift.rpe_translation_cm_per_m = cm_per_m / 2.0;
    drift.rpe_rotation_deg_per_m = deg_per_m / 2.0;
    result.drift = drift;
  }
  return result;
}

const Variant kNmRaw{"NM", false};
const Variant kGvtwDeskew{"GVTW", true};

std::vector<RunResult> sample_results() {
  return {result_of("cage-01", kNmRaw, RunStatus::Ok, 20.0, 5.0),
          result_of("cage-02", kNmRaw, RunStatus::Ok, 30.0, 7.0),
          result_of("cage-03", kNmRaw, RunStatus::Ok, 40.0, 9.0),
          result_of("cage-04", kNmRaw, RunStatus::Diverged, 500.0, 90.0, "translation error 500.0 cm/m > 100.0"),
          result_of("cage-05", kNmRaw, RunStatus::Failed, 0, 0, "no imu.pcap in /b/cage-05, \"really\""),
          result_of("cage-01", kGvtwDeskew, RunStatus::Ok, 3.0, 0.5)};
}

TEST(MatrixReport, CellStatisticsAreOverOkRunsWithTheOthersCounted) {
  const std::vector<CellSummary> cells = summarize_cells(sample_results(), {kNmRaw, kGvtwDeskew, {"SAW", true}});
  ASSERT_EQ(cells.size(), 3u);
  EXPECT_EQ(cells[0].runs, 5u);
  EXPECT_EQ(cells[0].ok, 3u);
  EXPECT_EQ(cells[0].diverged, 1u);
  EXPECT_EQ(cells[0].failed, 1u);
  EXPECT_DOUBLE_EQ(cells[0].translation_cm_per_m->median, 30.0);
  EXPECT_DOUBLE_EQ(cells[0].translation_cm_per_m->q1, 25.0);
  EXPECT_DOUBLE_EQ(cells[0].translation_cm_per_m->max, 40.0);
  EXPECT_DOUBLE_EQ(cells[0].rotation_deg_per_m->q3, 8.0);
  EXPECT_DOUBLE_EQ(cells[0].rpe_translation_cm_per_m->median, 15.0);
  EXPECT_EQ(cells[2].runs, 0u);
  EXPECT_FALSE(cells[2].translation_cm_per_m.has_value());
}

TEST(MatrixReport, MarkdownHasOneRowPerCellAndListsTheRunsNotEvaluated) {
  const std::vector<RunResult> results = sample_results();
  const std::vector<CellSummary> cells = summarize_cells(results, {kNmRaw, kGvtwDeskew});
  const std::string md =
      results_markdown(MatrixDescription{"/b", "cage runs", 5, EvalOptions{}, "boxplot.png"}, cells, results);
  EXPECT_NE(md.find("| no | NM | 3 | 1 | 1 | 30.00 | 25.00 | 35.00 | 40.00 | 7.00 | 6.00 | 8.00 | 9.00 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| yes | GVTW | 1 | 0 | 0 | 3.00 | 3.00 | 3.00 | 3.00 | 0.50 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| cage-04 | NM-no-deskew | diverged | translation error 500.0 cm/m > 100.0 |"), std::string::npos);
  EXPECT_NE(md.find("| cage-05 | NM-no-deskew | failed | no imu.pcap"), std::string::npos);
  EXPECT_NE(md.find("| NM without de-skew, median | 30.00 cm/m, 7.00 deg/m | 27.23 cm/m, 7.04 deg/m |"),
            std::string::npos);
  EXPECT_NE(md.find("![final pose error per model](boxplot.png)"), std::string::npos);
}

TEST(MatrixReport, CsvHasEveryJobWithQuotedMessages) {
  const TempDir dir("report");
  std::vector<RunResult> results = sample_results();
  results[0].runaway = Runaway{};
  results[0].runaway->largest = GoodStretch{1.0, 4.0, 30, 0.62};
  write_runs_csv(dir.path() / "runs.csv", results);
  const std::string csv = read_file(dir.path() / "runs.csv");
  std::vector<std::string> lines;
  for (std::size_t start = 0, end; (end = csv.find('\n', start)) != std::string::npos; start = end + 1)
    lines.push_back(csv.substr(start, end - start));
  ASSERT_EQ(lines.size(), 7u);
  EXPECT_EQ(
      lines[1],
      "cage-01,cage,NM,0,ok,,90,0,0,5.0000,1.00000,25.0000,20.0000,5.0000,40,10.0000,2.5000,10.000,4.000,2.50,2.0,,"
      "0.6200");
  EXPECT_EQ(lines[5],
            "cage-05,cage,NM,0,failed,\"no imu.pcap in /b/cage-05, \"\"really\"\"\",,0,0,,,,,,,,,10.000,"
            "4.000,2.50,2.0,,");  // no scan log: no runaway
  const auto fields_in = [](const std::string& line) { return std::count(line.begin(), line.end(), ',') + 1; };
  EXPECT_EQ(fields_in(lines[0]), 23);
  EXPECT_TRUE(lines[0].ends_with(",trajectory,runaway_growth_m")) << lines[0];
  EXPECT_EQ(fields_in(lines[1]), 23);
}

}  // namespace
}  // namespace tumble::eval
