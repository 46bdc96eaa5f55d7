#include "tools/eval/tum_file.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "test/tools/eval/eval_test_support.hpp"

namespace tumble::eval {
namespace {

using test::TempDir;
using test::write_file;

std::string error_of(const std::filesystem::path& path) {
  try {
    read_tum(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(TumFile, WritesWhatItReadsBack) {
  const TempDir dir("tum");
  PoseSeries series;
  series.push_back(TimedPose{1622032620.0, {7.0, 0.0, 0.35}, Eigen::Quaterniond(0.999255299, 0, 0, -0.038585578)});
  series.push_back(TimedPose{1622032620.1, {7.1, -0.2, 0.36}, Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5)});
  write_tum(dir.path() / "a.tum", series);
  const PoseSeries back = read_tum(dir.path() / "a.tum");
  ASSERT_EQ(back.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(back[i].t_s, series[i].t_s, 1e-8);
    EXPECT_TRUE(back[i].position_m.isApprox(series[i].position_m, 1e-9));
    EXPECT_NEAR(back[i].orientation.angularDistance(series[i].orientation.normalized()), 0.0, 1e-8);
  }
}

TEST(TumFile, SkipsCommentsAndBlankLines) {
  const TempDir dir("tum");
  write_file(dir.path() / "gt.tum",
             "# lidar pose T_WL\n# t x y z qx qy qz qw\n\n1.0 0 0 0 0 0 0 1\n  2.0 1 0 0 0 0 0 1\n");
  EXPECT_EQ(read_tum(dir.path() / "gt.tum").size(), 2u);
}

TEST(TumFile, NamesTheFileAndLineOfABadLine) {
  const TempDir dir("tum");
  const auto path = dir.path() / "bad.tum";
  write_file(path, "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n");
  EXPECT_EQ(error_of(path), path.string() + ":2: expected 8 numbers (t x y z qx qy qz qw), got 7 fields");
  write_file(path, "1.0 0 0 0 0 0 0 1\n2.0 0 0 x 0 0 0 1\n");
  EXPECT_EQ(error_of(path), path.string() + ":2: field 4 'x' is not a finite number");
  write_file(path, "1.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n");
  EXPECT_EQ(error_of(path), path.string() + ":2: time 1.0 does not increase");
  write_file(path, "1.0 0 0 0 0 0 0 2\n");
  EXPECT_NE(error_of(path).find(":1: quaternion is not unit"), std::string::npos);
  write_file(path, "1.0 0 0 0 0 0 0 nan\n");
  EXPECT_EQ(error_of(path), path.string() + ":1: field 8 'nan' is not a finite number");
  EXPECT_EQ(error_of(dir.path() / "absent.tum"), (dir.path() / "absent.tum").string() + ": cannot open");
}

}  // namespace
}  // namespace tumble::eval
