#include "tools/eval/box_plot.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include "test/tools/eval/eval_test_support.hpp"

namespace tumble::eval {
namespace {

using test::read_file;
using test::TempDir;

std::vector<CellSummary> sample_cells() {
  CellSummary nm;
  nm.variant = Variant{"NM", false};
  nm.translation_cm_per_m = box_stats({20, 25, 30, 35, 40, 200});
  nm.rotation_deg_per_m = box_stats({5, 6, 7});
  CellSummary gvtw;
  gvtw.variant = Variant{"GVTW", true};
  gvtw.translation_cm_per_m = box_stats({2, 3, 4});
  gvtw.rotation_deg_per_m = box_stats({0.4, 0.5});
  return {nm, gvtw};
}

TEST(BoxPlot, ScriptCarriesTheTableStatisticsAtEachModelsPlace) {
  const std::string script = box_plot_script(sample_cells(), "/out/boxplot.png");
  // NM is x = 1, blue; columns x q1 whisker_low whisker_high q3 median colour.
  // 20..40 and 200: Q1 26.25, Q3 38.75, fences 7.5 / 57.5 → whiskers 20 and 40, 200 an outlier.
  EXPECT_NE(script.find("$trans_raw << EOD\n1 26.25 20 40 38.75 32.5 0x1f77b4\nEOD\n"), std::string::npos) << script;
  EXPECT_NE(script.find("$trans_raw_out << EOD\n1 200\nEOD\n"), std::string::npos);
  EXPECT_NE(script.find("$rot_deskew << EOD\n4 0.425 0.4 0.5 0.475 0.45 0xd62728\nEOD\n"), std::string::npos);
  EXPECT_NE(script.find("set output '/out/boxplot.png'"), std::string::npos);
  EXPECT_NE(script.find("set xtics ('NM' 1, 'TW' 2, 'VTW' 3, 'GVTW' 4, 'SAW' 5)"), std::string::npos);
}

TEST(BoxPlot, GnuplotDrawsAPng) {
  if (access("/usr/bin/gnuplot", X_OK) != 0) GTEST_SKIP() << "gnuplot not installed (Debian package gnuplot-nox)";
  const TempDir dir("plot");
  std::vector<CellSummary> cells = sample_cells();
  cells.push_back(CellSummary{Variant{"SAW", true}});  // a cell without data
  ASSERT_EQ(draw_box_plot(cells, dir.path() / "boxplot.gp", dir.path() / "boxplot.png"), "");
  const std::string png = read_file(dir.path() / "boxplot.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
}

TEST(BoxPlot, AllPanelsEmptyStillDraws) {
  if (access("/usr/bin/gnuplot", X_OK) != 0) GTEST_SKIP() << "gnuplot not installed (Debian package gnuplot-nox)";
  const TempDir dir("plot");
  EXPECT_EQ(draw_box_plot({CellSummary{Variant{"NM", false}}}, dir.path() / "b.gp", dir.path() / "b.png"), "");
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "b.png"));
}

}  // namespace
}  // namespace tumble::eval
