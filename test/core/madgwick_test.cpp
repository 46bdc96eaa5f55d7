// Madgwick IMU filter: converges to a known static tilt, tracks a constant
// rate, and the accelerometer gate ignores shocks.
#include "core/madgwick.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace tumble {
namespace {

constexpr double kGravity_m_s2 = 9.80665;

Eigen::Quaterniond rpy(double roll, double pitch, double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

// What a still accelerometer with attitude q_wi measures: +g up, in the IMU frame.
Eigen::Vector3d specific_force_at_rest(const Eigen::Quaterniond& q_wi) {
  return q_wi.conjugate() * Eigen::Vector3d(0, 0, kGravity_m_s2);
}

// Angle between the "up" directions two attitudes predict (roll/pitch error).
double tilt_error_rad(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Vector3d up_a = a.conjugate() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d up_b = b.conjugate() * Eigen::Vector3d::UnitZ();
  return std::atan2(up_a.cross(up_b).norm(), up_a.dot(up_b));
}

TEST(Madgwick, ConvergesToAStaticTilt) {
  const Eigen::Quaterniond truth = rpy(0.3, -0.2, 0.5);
  MadgwickFilter filter(MadgwickParams{}, Eigen::Quaterniond::Identity(), kGravity_m_s2);
  ASSERT_GT(tilt_error_rad(filter.orientation(), truth), 0.3);
  for (int i = 0; i < 3000; ++i) {
    EXPECT_TRUE(filter.update(Eigen::Vector3d::Zero(), specific_force_at_rest(truth), 0.01));
  }
  EXPECT_LT(tilt_error_rad(filter.orientation(), truth), 1e-6);
}

TEST(Madgwick, SettlesWithoutChatteringOnceTheTiltErrorIsBelowOneStep) {
  // 0.3 mrad off, less than one step: an uncapped step (β·dt = 1e-3 of
  // quaternion, a 2 mrad turn at 100 Hz) overshoots to the other side and
  // keeps turning the attitude by ~2 mrad per sample.
  const Eigen::Quaterniond truth = rpy(0.2, 0.1, 0.0);
  const Eigen::Quaterniond start = truth * Eigen::Quaterniond(Eigen::AngleAxisd(3e-4, Eigen::Vector3d::UnitX()));
  MadgwickFilter filter(MadgwickParams{}, start, kGravity_m_s2);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Quaterniond before = filter.orientation();
    filter.update(Eigen::Vector3d::Zero(), specific_force_at_rest(truth), 0.01);
    EXPECT_LT(tilt_error_rad(filter.orientation(), truth), 3e-4 + 1e-12) << "step " << i;
    if (i > 0) {
      EXPECT_LT(filter.orientation().angularDistance(before), 1e-5) << "step " << i;
    }
  }
  EXPECT_LT(tilt_error_rad(filter.orientation(), truth), 1e-9);
}

TEST(Madgwick, GyroPropagationIsExactForAConstantRate) {
  const Eigen::Vector3d omega(0.5, -1.0, 11.0);
  const Eigen::Quaterniond start = rpy(0.1, 0.2, 0.3);
  MadgwickFilter filter(MadgwickParams{}, start, kGravity_m_s2);
  for (int i = 0; i < 500; ++i) filter.propagate(omega, 0.01);
  const Eigen::Quaterniond truth =
      start * Eigen::Quaterniond(Eigen::AngleAxisd(5.0 * omega.norm(), omega.normalized()));
  EXPECT_LT(filter.orientation().angularDistance(truth), 1e-9);
}

TEST(Madgwick, TracksAConstantRateRotationWithGravity) {
  const Eigen::Vector3d omega(0.5, -1.0, 11.0);  // 11 rad/s: the paper's turntable
  const Eigen::Quaterniond start = rpy(0.1, 0.2, 0.3);
  MadgwickFilter filter(MadgwickParams{}, start, kGravity_m_s2);
  for (int i = 1; i <= 500; ++i) {
    const double t = 0.01 * i;
    const Eigen::Quaterniond truth =
        start * Eigen::Quaterniond(Eigen::AngleAxisd(t * omega.norm(), omega.normalized()));
    filter.update(omega, specific_force_at_rest(truth), 0.01);
    ASSERT_LT(filter.orientation().angularDistance(truth), 1e-2) << "t = " << t;
  }
}

TEST(Madgwick, GateIgnoresAShock) {
  const Eigen::Quaterniond level = Eigen::Quaterniond::Identity();
  const Eigen::Vector3d shock = specific_force_at_rest(level) + Eigen::Vector3d(200.0, 0.0, 0.0);
  MadgwickFilter gated(MadgwickParams{}, level, kGravity_m_s2);
  MadgwickParams no_gate;
  no_gate.accel_gate_m_s2 = 1e9;
  MadgwickFilter ungated(no_gate, level, kGravity_m_s2);
  for (int i = 0; i < 50; ++i) {
    EXPECT_FALSE(gated.update(Eigen::Vector3d::Zero(), shock, 0.01));
    EXPECT_TRUE(ungated.update(Eigen::Vector3d::Zero(), shock, 0.01));
  }
  EXPECT_LT(gated.orientation().angularDistance(level), 1e-12);
  // Without the gate, 50 steps of β·dt toward the shock's "up" tilt it by ~0.1 rad.
  EXPECT_GT(tilt_error_rad(ungated.orientation(), level), 0.05);
}

TEST(Madgwick, GateUsesTheGivenGravity) {
  // An accelerometer reading 5 % high still corrects when the filter was told so.
  const Eigen::Quaterniond truth = rpy(0.2, 0.0, 0.0);
  const double g_measured = 1.05 * kGravity_m_s2;
  MadgwickFilter filter(MadgwickParams{}, Eigen::Quaterniond::Identity(), g_measured);
  EXPECT_TRUE(filter.update(Eigen::Vector3d::Zero(), g_measured / kGravity_m_s2 * specific_force_at_rest(truth), 0.01));
}

}  // namespace
}  // namespace tumble
