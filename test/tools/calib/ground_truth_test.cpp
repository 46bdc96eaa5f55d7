// ground_truth.tum: parsed strictly (errors name file and line), interpolated
// between samples, and the speeds and travel the calibration bins by.
#include "tools/calib/ground_truth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "test/tools/calib/temp_dir.hpp"
#include "tools/calib/input_error.hpp"

namespace tumble::calib {
namespace {

using test::TempDir;
using test::write_file;

// Rest for 1 s, then a 2 rad/s turn about z while moving 0.5 m/s along −y, 1 kHz.
std::string moving_tum() {
  std::ostringstream out;
  out.precision(12);
  out << "# t x y z qx qy qz qw\n";
  for (int i = 0; i <= 3000; ++i) {
    const double t = 100.0 + i * 1e-3;
    const double moving = std::max(0.0, t - 101.0);
    const double yaw = 2.0 * moving;
    out << t << " 1 " << -0.5 * moving << " 2 0 0 " << std::sin(yaw / 2) << ' ' << std::cos(yaw / 2) << '\n';
  }
  return out.str();
}

std::string load_error(const std::string& text) {
  TempDir dir;
  write_file(dir.path() / "gt.tum", text);
  try {
    GroundTruth::load(dir.path() / "gt.tum");
  } catch (const InputError& e) {
    const std::string what = e.what();
    return what.substr(what.find("gt.tum"));
  }
  return "no error";
}

TEST(GroundTruth, ReadsPosesAndInterpolatesBetweenThem) {
  TempDir dir;
  write_file(dir.path() / "gt.tum", moving_tum());
  const GroundTruth gt = GroundTruth::load(dir.path() / "gt.tum");
  EXPECT_DOUBLE_EQ(gt.t_begin_s(), 100.0);
  EXPECT_NEAR(gt.t_end_s(), 103.0, 1e-9);
  const Eigen::Isometry3d T = gt.pose_at(102.0005);  // between two samples
  EXPECT_NEAR(T.translation().y(), -0.5 * 1.0005, 1e-9);
  EXPECT_NEAR(Eigen::AngleAxisd(T.linear()).angle(), 2.0 * 1.0005, 1e-9);
  EXPECT_TRUE(gt.covers(100.5, 102.5));
  EXPECT_FALSE(gt.covers(99.9, 100.5));
  EXPECT_NEAR(gt.pose_at(50.0).translation().y(), 0.0, 1e-12);  // clamped before the start
}

TEST(GroundTruth, GivesSpeedsMotionStartAndTravelDirection) {
  TempDir dir;
  write_file(dir.path() / "gt.tum", moving_tum());
  const GroundTruth gt = GroundTruth::load(dir.path() / "gt.tum");
  EXPECT_NEAR(gt.mean_linear_speed_m_s(101.5, 101.6), 0.5, 1e-6);
  EXPECT_NEAR(gt.mean_angular_rate_rad_s(101.5, 101.6), 2.0, 1e-6);
  EXPECT_NEAR(gt.mean_linear_speed_m_s(100.1, 100.2), 0.0, 1e-12);
  EXPECT_NEAR(gt.motion_start_s(), 101.001, 1.5e-3);
  EXPECT_TRUE(gt.travel_direction().isApprox(Eigen::Vector3d(0, -1, 0), 1e-9));
}

TEST(GroundTruth, BadFilesNameTheLineAndTheProblem) {
  const std::string good = "0 0 0 0 0 0 0 1\n";
  EXPECT_EQ(load_error(good + "0.1 0 0 0 0 0 0\n"), "gt.tum:2: expected 8 numbers \"t x y z qx qy qz qw\"");
  EXPECT_EQ(load_error(good + "0.1 0 0 0 0 0 0 1 9\n"), "gt.tum:2: more than 8 fields");
  EXPECT_EQ(load_error(good + "0.1 0 nan 0 0 0 0 1\n"), "gt.tum:2: expected 8 numbers \"t x y z qx qy qz qw\"");
  EXPECT_EQ(load_error(good + "0.1 0 0 0 0 0 0 2\n").substr(0, 33), "gt.tum:2: quaternion is not unit ");
  EXPECT_EQ(load_error(good + "0 0 0 0 0 0 0 1\n").substr(0, 24), "gt.tum:2: time 0.000000 ");
  EXPECT_EQ(load_error(good), "gt.tum: fewer than 2 poses");
  EXPECT_EQ(load_error("\x89PNG\r\n\x1a\n"), "gt.tum:1: expected 8 numbers \"t x y z qx qy qz qw\"");
}

}  // namespace
}  // namespace tumble::calib
