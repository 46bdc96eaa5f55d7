// The rolling cage: rolls without slipping on the ground, bounces never go
// below the ground and peak exactly, events are seeded and deterministic.
#include "test/tools/sim/motion_checks.hpp"
#include "tools/sim/motion_rolling_cage.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace tumble::sim {
namespace {

ScalarProfile pull(double rate_rad_s, double hold_s) {
  ScalarProfile p;
  p.hold(0.5);
  p.change_velocity(rate_rad_s, 25.0, 0.1);
  p.hold(hold_s);
  p.change_velocity(0.0, 15.0, 0.2);
  p.hold(0.5);
  return p;
}

// The cage's material point touching the ground (below the centre) moves with
// v_centre + omega x (contact - centre); rolling without slipping makes it 0.
Eigen::Vector3d contact_velocity(const MotionState& centre, double radius) {
  const Eigen::Vector3d omega_w = centre.T_wb.linear() * centre.omega_b;
  return centre.v_w + omega_w.cross(Eigen::Vector3d(0, 0, -radius));
}

RollingCageParams explicit_events() {
  RollingCageParams p;
  p.radius_m = 0.25;
  p.roll_rad = pull(10.0, 4.0);
  p.bounces.push_back({1.5, 0.12, 200.0});
  p.jolts.push_back({3.0, 800.0, 1.0});
  p.jolts.push_back({3.5, -600.0, 0.5});
  p.mount = pose_from_xyz_rpy_deg({0.05, 0.0, 0.03}, {90, 0, 0});
  return p;
}

TEST(RollingCage, RollsWithoutSlippingOutsideBounces) {
  const RollingCageMotion cage(explicit_events());
  int checked = 0;
  for (double t = 0; t <= cage.duration_s(); t += 2e-3) {
    if (cage.in_bounce(t)) continue;
    const MotionState c = cage.cage_at(t);
    EXPECT_NEAR(c.T_wb.translation().z(), 0.25, 1e-12) << "t=" << t;
    EXPECT_LT(contact_velocity(c, 0.25).norm(), 1e-12) << "t=" << t;
    ++checked;
  }
  EXPECT_GT(checked, 2500);
}

TEST(RollingCage, HorizontalTravelIsRadiusTimesRollAngle) {
  const RollingCageMotion cage(explicit_events());
  for (double t = 0; t <= cage.duration_s(); t += 0.01) {
    const MotionState c = cage.cage_at(t);
    // Roll angle about +y recovered from the orientation (it stays a pure y rotation).
    const Eigen::Matrix3d R = c.T_wb.linear();
    EXPECT_NEAR(R(1, 1), 1.0, 1e-12);
    const double roll = std::atan2(R(0, 2), R(0, 0));
    const double x = c.T_wb.translation().x();
    const double wrapped = std::remainder(x / 0.25 - roll, 2 * std::numbers::pi);
    EXPECT_NEAR(wrapped, 0.0, 1e-9) << "t=" << t;
  }
}

TEST(RollingCage, BounceStaysAboveGroundAndReachesItsApexAndPeak) {
  const ScalarProfile b = bounce_profile(0.0, 0.12, 200.0);
  double apex = 0, lowest = 1, peak = -1e9;
  for (double t = 0; t <= b.end_s(); t += 1e-6) {
    const ProfileSample s = b.at(t);
    apex = std::max(apex, s.s);
    lowest = std::min(lowest, s.s);
    peak = std::max(peak, s.a);
  }
  EXPECT_NEAR(apex, 0.12, 1e-9);
  EXPECT_GE(lowest, -1e-15);
  EXPECT_NEAR(peak, 200.0, 1e-6);
  EXPECT_LE(b.max_abs_accel(), 200.0 + 1e-9);
  EXPECT_NEAR(b.end_state().s, 0.0, 1e-12) << "lands back at height R";
  EXPECT_NEAR(b.end_state().v, 0.0, 1e-12) << "and at rest vertically";
  EXPECT_NEAR(b.end_s(), bounce_duration_s(0.12, 200.0), 1e-12);
  // Free flight in between: exactly -g.
  EXPECT_NEAR(b.at(b.end_s() / 2).a, -kStandardGravity_m_s2, 1e-12);
}

TEST(RollingCage, DerivativesIncludingImpacts) {
  const RollingCageParams p = explicit_events();
  const RollingCageMotion cage(p);
  const double bounce_end = p.bounces[0].t_start_s + bounce_duration_s(0.12, 200.0);
  std::vector<double> extra;
  for (double f : {0.001, 0.004, 0.007, 0.011}) {
    extra.push_back(p.bounces[0].t_start_s + f);
    extra.push_back(bounce_end - f);
  }
  for (const CageJolt& j : p.jolts)
    for (double f : {0.1, 0.3, 0.55, 0.9}) extra.push_back(j.t_start_s + f * jolt_duration_s(j.peak_accel_rad_s2, j.rate_swing_rad_s));
  test::DerivativeTolerance tol;
  tol.a_m_s2 = 3e-3;
  tol.alpha_rad_s2 = 5e-3;
  test::expect_derivatives(cage, 300, extra, tol);
}

TEST(RollingCage, AccelerationIsContinuousAtEveryEventBoundary) {
  const RollingCageParams p = explicit_events();
  const RollingCageMotion cage(p);
  std::vector<double> boundaries;
  for (const auto& seg : p.roll_rad.segments()) boundaries.push_back(seg.t0);
  const ScalarProfile bounce = bounce_profile(p.bounces[0].t_start_s, 0.12, 200.0);
  for (const auto& seg : bounce.segments()) boundaries.push_back(seg.t0);
  for (const CageJolt& j : p.jolts) {
    boundaries.push_back(j.t_start_s);
    boundaries.push_back(j.t_start_s + jolt_duration_s(j.peak_accel_rad_s2, j.rate_swing_rad_s));
  }
  for (double t : boundaries) {
    const MotionState lo = cage.at(t - 1e-10), hi = cage.at(t + 1e-10);
    EXPECT_LT((hi.a_w - lo.a_w).norm(), 1e-3) << "t=" << t;
    EXPECT_LT((hi.alpha_b - lo.alpha_b).norm(), 1e-3) << "t=" << t;
  }
}

TEST(RollingCage, PeaksMatchTheEventsExactly) {
  RollingCageParams p = explicit_events();
  p.mount = Eigen::Isometry3d::Identity();  // at the centre: no lever-arm terms
  const RollingCageMotion cage(p);
  const test::Peaks peaks = test::sweep_peaks(cage, 1.5e-3);  // shortest bump: half of a 4 * 0.5 / 600 = 3.3 ms jolt
  // Jolt: 800 rad/s^2 at a 0.25 m radius is 200 m/s^2 at the centre; bounce: 200 m/s^2 up.
  EXPECT_NEAR(peaks.angular_accel_rad_s2, 800.0, 1e-3);
  EXPECT_LE(peaks.angular_accel_rad_s2, 800.0 + 1e-9);
  EXPECT_NEAR(peaks.accel_m_s2, 200.0, 1e-3);
  EXPECT_LE(peaks.accel_m_s2, 200.0 + 1e-9);
  EXPECT_NEAR(peaks.rate_rad_s, 11.0, 1e-6) << "10 rad/s plus the 1 rad/s jolt swing";
  EXPECT_LE(peaks.rate_rad_s, 11.0 + 1e-9);
}

TEST(RollingCage, SeededEventsAreDeterministicAndDifferBySeed) {
  CageEventRanges r;
  r.bounce_count = 3;
  r.jolt_count = 5;
  auto events = [&](std::uint64_t seed) {
    RollingCageParams p;
    p.roll_rad = pull(10.0, 8.0);
    place_cage_events(p, r, seed);
    return p;
  };
  const RollingCageParams a = events(7), b = events(7), c = events(8);
  ASSERT_EQ(a.bounces.size(), 3u);
  ASSERT_EQ(a.jolts.size(), 5u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(a.bounces[i].t_start_s, b.bounces[i].t_start_s);
    EXPECT_EQ(a.bounces[i].height_m, b.bounces[i].height_m);
  }
  EXPECT_NE(a.bounces[0].t_start_s, c.bounces[0].t_start_s);
  // Inside the constant-rate part and within the ranges; the motion accepts them (no overlap).
  const double hold_begin = 0.5 + 10.0 / 25.0 + 0.1, hold_end = hold_begin + 8.0;
  for (const CageBounce& bounce : a.bounces) {
    EXPECT_GE(bounce.t_start_s, hold_begin);
    EXPECT_LE(bounce.t_start_s + bounce_duration_s(bounce.height_m, bounce.peak_accel_m_s2), hold_end + 1e-12);
    EXPECT_GE(bounce.peak_accel_m_s2, r.bounce_peak_min_m_s2);
    EXPECT_LE(bounce.peak_accel_m_s2, r.bounce_peak_max_m_s2);
  }
  for (const CageJolt& j : a.jolts) {
    EXPECT_GE(std::abs(j.peak_accel_rad_s2), r.jolt_peak_min_rad_s2);
    EXPECT_LE(std::abs(j.peak_accel_rad_s2), r.jolt_peak_max_rad_s2);
  }
  EXPECT_NO_THROW(RollingCageMotion{a});
  const RollingCageMotion m1(a), m2(b);
  for (double t = 0; t < m1.duration_s(); t += 0.37) EXPECT_TRUE(m1.at(t).T_wb.isApprox(m2.at(t).T_wb, 0));
}

TEST(RollingCage, TooManyEventsDoNotFit) {
  CageEventRanges r;
  r.bounce_count = 200;
  RollingCageParams p;
  p.roll_rad = pull(10.0, 2.0);
  try {
    place_cage_events(p, r, 1);
    FAIL() << "200 bounces cannot fit in 2 s";
  } catch (const CageEventsDoNotFit& e) {
    EXPECT_EQ(e.key, "bounces.count");
  }
}

TEST(RollingCage, OverlappingExplicitEventsAreRefused) {
  RollingCageParams p = explicit_events();
  p.jolts.push_back({p.bounces[0].t_start_s + 0.01, 500.0, 0.5});
  EXPECT_THROW(RollingCageMotion{p}, std::invalid_argument);
}

}  // namespace
}  // namespace tumble::sim
