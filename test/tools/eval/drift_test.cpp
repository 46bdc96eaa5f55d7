#include "tools/eval/drift.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>

namespace tumble::eval {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

Eigen::Isometry3d make_pose(const Eigen::Vector3d& axis, double angle_rad, const Eigen::Vector3d& translation_m) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  pose.translation() = translation_m;
  return pose;
}

TimedPose timed(double t_s, const Eigen::Isometry3d& pose) {
  return TimedPose{t_s, pose.translation(), Eigen::Quaterniond(pose.linear())};
}

// Ground truth: 1 m/s along a straight line for 10 s, sampled at 1 kHz, the
// line placed anywhere in the world (as the simulator's frame is).
const Eigen::Isometry3d kWorldFromStart = make_pose({0.3, -1.0, 0.2}, 0.7, {7.0, -3.0, 0.35});
constexpr double kT0 = 1622032620.0;

PoseSeries straight_ground_truth() {
  PoseSeries series;
  for (int i = 0; i <= 10000; ++i) {
    const double s_m = i * 1e-3;
    series.push_back(timed(kT0 + s_m, kWorldFromStart * make_pose({0, 0, 1}, 0.0, {s_m, 0.0, 0.0})));
  }
  return series;
}

// An estimate at 10 Hz in its own frame (anywhere), between samples of the
// ground truth, with one pose before and one after the ground truth (unused).
// motion(s) is the estimated pose after s metres of true travel.
PoseSeries estimate_of(const std::function<Eigen::Isometry3d(double)>& motion) {
  const Eigen::Isometry3d own_frame = make_pose({1.0, 1.0, 0.0}, -2.0, {-40.0, 12.0, 3.0});
  PoseSeries series{timed(kT0 - 0.5, own_frame)};
  for (int i = 0; i < 100; ++i) {
    const double s_m = 0.05 + 0.1 * i;
    series.push_back(timed(kT0 + s_m, own_frame * motion(s_m)));
  }
  series.push_back(timed(kT0 + 10.5, own_frame));
  return series;
}

TEST(Drift, ScaleErrorOf2PercentIs2CmPerMetreFinalAndRelative) {
  const DriftResult drift = evaluate_drift(straight_ground_truth(), estimate_of([](double s_m) {
                                             return make_pose({0, 0, 1}, 0.0, {1.02 * s_m, 0, 0});
                                           }),
                                           DriftOptions{});
  EXPECT_EQ(drift.poses, 100u);
  EXPECT_NEAR(drift.distance_m, 9.9, 1e-9);
  EXPECT_NEAR(drift.final_translation_error_m, 0.02 * 9.9, 1e-9);
  EXPECT_NEAR(drift.translation_cm_per_m, 2.0, 1e-7);
  EXPECT_NEAR(drift.rotation_deg_per_m, 0.0, 1e-6);
  // Segments of ≥ 1 m start at every pose up to 1 m before the end.
  EXPECT_GE(drift.rpe_segments, 89u);
  EXPECT_LE(drift.rpe_segments, 90u);
  EXPECT_NEAR(drift.rpe_translation_cm_per_m, 2.0, 1e-6);
  EXPECT_NEAR(drift.rpe_rotation_deg_per_m, 0.0, 1e-6);
}

TEST(Drift, YawDriftOf1DegreePerMetre) {
  // Heading error grows by 1° per metre travelled; the position follows the
  // truth, so the final translation error after aligning at the first pose is 0.
  const double rate_rad_per_m = 1.0 / kDegPerRad;
  const DriftResult drift = evaluate_drift(straight_ground_truth(), estimate_of([&](double s_m) {
                                             return make_pose({0, 0, 1}, rate_rad_per_m * (s_m - 0.05), {s_m, 0, 0});
                                           }),
                                           DriftOptions{});
  EXPECT_NEAR(drift.final_rotation_error_deg, 9.9, 1e-7);
  EXPECT_NEAR(drift.rotation_deg_per_m, 1.0, 1e-7);
  EXPECT_NEAR(drift.final_translation_error_m, 0.0, 1e-9);
  EXPECT_NEAR(drift.rpe_rotation_deg_per_m, 1.0, 1e-6);
}

TEST(Drift, LongerSegmentsAverageTheSameConstantDrift) {
  const DriftResult drift = evaluate_drift(straight_ground_truth(), estimate_of([](double s_m) {
                                             return make_pose({0, 0, 1}, 0.0, {0.95 * s_m, 0, 0});
                                           }),
                                           DriftOptions{4.0});
  EXPECT_NEAR(drift.rpe_translation_cm_per_m, 5.0, 1e-6);
  EXPECT_GE(drift.rpe_segments, 59u);
  EXPECT_LE(drift.rpe_segments, 60u);
}

TEST(Drift, NoRpeSegmentWhenTheRunIsShorterThanOne) {
  const DriftResult drift = evaluate_drift(straight_ground_truth(), estimate_of([](double s_m) {
                                             return make_pose({0, 0, 1}, 0.0, {s_m, 0, 0});
                                           }),
                                           DriftOptions{20.0});
  EXPECT_EQ(drift.rpe_segments, 0u);
  EXPECT_TRUE(std::isnan(drift.rpe_translation_cm_per_m));
  EXPECT_NEAR(drift.translation_cm_per_m, 0.0, 1e-7);
}

TEST(Drift, RelativeMotionErrorIsThePositionErrorAfterAligningAtTheStart) {
  const Eigen::Isometry3d truth_a = make_pose({1, 2, 3}, 0.4, {1, 2, 3});
  const Eigen::Isometry3d truth_b = make_pose({-1, 0, 3}, 1.4, {4, -2, 0});
  const Eigen::Isometry3d estimate_a = make_pose({0, 1, 0}, -0.3, {10, 0, 0});
  const Eigen::Isometry3d estimate_b = make_pose({2, 1, 1}, 2.0, {13, 5, 1});
  const Eigen::Isometry3d aligned_b = truth_a * estimate_a.inverse() * estimate_b;
  const Eigen::Isometry3d error = relative_motion_error(truth_a, truth_b, estimate_a, estimate_b);
  EXPECT_NEAR(error.translation().norm(), (aligned_b.translation() - truth_b.translation()).norm(), 1e-12);
  EXPECT_NEAR(rotation_angle_deg(error.linear()), rotation_angle_deg(truth_b.linear().transpose() * aligned_b.linear()),
              1e-9);
}

TEST(Drift, RefusesEstimatesItCannotJudge) {
  const PoseSeries truth = straight_ground_truth();
  const PoseSeries one_inside = {timed(kT0 - 1.0, Eigen::Isometry3d::Identity()),
                                 timed(kT0 + 1.0, Eigen::Isometry3d::Identity())};
  EXPECT_THROW(evaluate_drift(truth, one_inside, DriftOptions{}), std::invalid_argument);
  PoseSeries standing_still;
  for (int i = 0; i <= 100; ++i) standing_still.push_back(timed(kT0 + 0.01 * i, Eigen::Isometry3d::Identity()));
  EXPECT_THROW(evaluate_drift(standing_still, standing_still, DriftOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace tumble::eval
