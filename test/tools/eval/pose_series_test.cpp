#include "tools/eval/pose_series.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace tumble::eval {
namespace {

TimedPose pose(double t_s, Eigen::Vector3d position_m, double yaw_rad) {
  return TimedPose{t_s, position_m, Eigen::Quaterniond(Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()))};
}

TEST(PoseSeries, InterpolatesPositionLinearlyAndRotationBySlerp) {
  const PoseSeries series = {pose(10.0, {0, 0, 0}, 0.0), pose(12.0, {2, 4, -2}, 1.0)};
  const Eigen::Isometry3d mid = pose_at(series, 10.5);
  EXPECT_TRUE(mid.translation().isApprox(Eigen::Vector3d(0.5, 1.0, -0.5), 1e-12));
  EXPECT_NEAR(Eigen::AngleAxisd(mid.linear()).angle(), 0.25, 1e-12);
  EXPECT_TRUE(pose_at(series, 12.0).translation().isApprox(Eigen::Vector3d(2, 4, -2), 1e-12));
}

TEST(PoseSeries, RefusesTimesOutsideItsSpan) {
  const PoseSeries series = {pose(1.0, {0, 0, 0}, 0.0), pose(2.0, {1, 0, 0}, 0.0)};
  EXPECT_THROW(pose_at(series, 0.999), std::out_of_range);
  EXPECT_THROW(pose_at(series, 2.001), std::out_of_range);
  EXPECT_THROW(pose_at(PoseSeries{series.front()}, 1.0), std::out_of_range);
}

TEST(PoseSeries, TheSampleAtAScansTimeIsFoundWithinATenthOfAMillisecond) {
  const PoseSeries series = {pose(1.0, {0, 0, 0}, 0.0), pose(1.1, {1, 0, 0}, 0.0), pose(1.2, {2, 0, 0}, 0.0)};
  ASSERT_TRUE(sample_at(series, 1.10005).has_value());
  EXPECT_DOUBLE_EQ(sample_at(series, 1.10005)->position_m.x(), 1.0);
  EXPECT_FALSE(sample_at(series, 1.15).has_value());  // between samples: not interpolated
  EXPECT_FALSE(sample_at(series, 1.2002).has_value());
  EXPECT_FALSE(sample_at(PoseSeries{}, 1.0).has_value());
}

TEST(PoseSeries, PathLengthOfAQuarterCircleSampledAt1kHz) {
  // Radius 2 m, a quarter turn in 1 s: the chord sum falls short of πr/2 by
  // about (πr/2)·(Δθ)²/24, Δθ = (π/2)/1000, i.e. 3e-7 m.
  PoseSeries circle;
  for (int i = 0; i <= 1000; ++i) {
    const double angle = std::numbers::pi / 2.0 * i / 1000.0;
    circle.push_back(pose(i * 1e-3, {2.0 * std::cos(angle), 2.0 * std::sin(angle), 0.0}, angle));
  }
  EXPECT_NEAR(path_length_m(circle, 0.0, 1.0), std::numbers::pi, 1e-6);
  // Half of it, starting and ending between samples.
  EXPECT_NEAR(path_length_m(circle, 0.2505, 0.7505), std::numbers::pi / 2.0, 1e-6);
  EXPECT_DOUBLE_EQ(path_length_m(circle, 0.3, 0.3), 0.0);
  EXPECT_THROW(path_length_m(circle, 0.5, 0.4), std::invalid_argument);
}

TEST(PoseSeries, RotationAngleIsAccurateNearZeroAndAtLargeAngles) {
  for (const double angle_deg : {1e-6, 0.5, 90.0, 179.0}) {
    const Eigen::Matrix3d rotation =
        Eigen::AngleAxisd(angle_deg * std::numbers::pi / 180.0, Eigen::Vector3d(1, 2, 3).normalized())
            .toRotationMatrix();
    EXPECT_NEAR(rotation_angle_deg(rotation), angle_deg, 1e-9 * std::max(1.0, angle_deg));
  }
}

}  // namespace
}  // namespace tumble::eval
