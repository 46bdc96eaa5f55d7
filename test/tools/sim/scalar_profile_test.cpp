// The 1-D profiles: closed forms agree with differences, peaks are exact,
// and acceleration is continuous at every segment boundary.
#include "tools/sim/scalar_profile.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace tumble::sim {
namespace {

// Central differences; the step for each derivative balances truncation
// (short pulses have large higher derivatives) against rounding.
void expect_consistent(const ScalarProfile& p, int samples) {
  const double h = 1e-6, h_fine = 1e-7;
  for (int i = 0; i < samples; ++i) {
    const double t = p.start_s() + (p.end_s() - p.start_s()) * (i + 0.5) / samples;
    const ProfileSample s = p.at(t), lo = p.at(t - h), hi = p.at(t + h);
    const ProfileSample lo_fine = p.at(t - h_fine), hi_fine = p.at(t + h_fine);
    // Truncation of the central difference is h^2 / 6 * jerk.
    EXPECT_NEAR((hi.s - lo.s) / (2 * h), s.v, 1e-7 + h * h * std::abs(s.jerk) / 3) << "t=" << t;
    EXPECT_NEAR((hi_fine.v - lo_fine.v) / (2 * h_fine), s.a, 1e-4) << "t=" << t;
    EXPECT_NEAR((hi.a - lo.a) / (2 * h), s.jerk, 1e-2 * std::max(1.0, std::abs(s.jerk) * 1e-3)) << "t=" << t;
  }
}

void expect_continuous_acceleration(const ScalarProfile& p) {
  for (const auto& seg : p.segments()) {
    const double eps = 1e-10;
    EXPECT_NEAR(p.at(seg.t0 - eps).a, p.at(seg.t0 + eps).a, 1e-4) << "boundary at t=" << seg.t0;
    EXPECT_NEAR(p.at(seg.t0 - eps).v, p.at(seg.t0 + eps).v, 1e-6) << "boundary at t=" << seg.t0;
  }
}

double sampled_max_abs_accel(const ScalarProfile& p) {
  double m = 0;
  for (double t = p.start_s(); t <= p.end_s(); t += 1e-6) m = std::max(m, std::abs(p.at(t).a));
  return m;
}

TEST(ScalarProfile, RaisedCosineVelocityChangeHitsThePeakExactly) {
  ScalarProfile p;
  p.hold(0.5);
  ASSERT_TRUE(p.change_velocity(3.5, 200.0));
  EXPECT_NEAR(p.end_state().v, 3.5, 1e-12);
  EXPECT_NEAR(p.end_state().a, 0.0, 1e-9);
  EXPECT_NEAR(p.end_s() - 0.5, 2 * 3.5 / 200.0, 1e-15) << "duration = 2 dv / peak";
  EXPECT_NEAR(p.max_abs_accel(), 200.0, 1e-9);
  EXPECT_NEAR(p.at(0.5 + 3.5 / 200.0).a, 200.0, 1e-9) << "the peak is at the middle";
  EXPECT_LE(sampled_max_abs_accel(p), 200.0 + 1e-9);
  expect_consistent(p, 200);
  expect_continuous_acceleration(p);
}

TEST(ScalarProfile, JerkLimitedRampHasAPlateau) {
  ScalarProfile p;
  ASSERT_TRUE(p.change_velocity(-3.0, 4.0, 0.25));
  EXPECT_NEAR(p.end_state().v, -3.0, 1e-12);
  EXPECT_NEAR(p.end_s(), 3.0 / 4.0 + 0.25, 1e-12) << "rise + plateau + fall";
  EXPECT_NEAR(p.at(0.5).a, -4.0, 1e-12);
  EXPECT_NEAR(p.max_abs_accel(), 4.0, 1e-12);
  EXPECT_FALSE(p.change_velocity(0.0, 4.0, 0.8)) << "rise longer than |dv| / peak allows";
  EXPECT_NEAR(p.end_state().v, -3.0, 1e-12) << "a refused step appends nothing";
  expect_consistent(p, 100);
  expect_continuous_acceleration(p);
}

TEST(ScalarProfile, TravelIsRestToRestAndReachesTheDistance) {
  ScalarProfile longer;
  longer.travel(25.0, 3.5, 4.0);
  EXPECT_NEAR(longer.end_state().s, 25.0, 1e-12);
  EXPECT_NEAR(longer.end_state().v, 0.0, 1e-12);
  EXPECT_NEAR(longer.max_abs_velocity(), 3.5, 1e-12);
  EXPECT_NEAR(longer.max_abs_accel(), 4.0, 1e-12);
  ScalarProfile shorter;  // too short to reach max_v: the peak speed is lowered, peak accel kept
  shorter.travel(-1.0, 3.5, 4.0);
  EXPECT_NEAR(shorter.end_state().s, -1.0, 1e-12);
  EXPECT_NEAR(shorter.max_abs_velocity(), std::sqrt(1.0 * 4.0 / 2), 1e-12);
  EXPECT_NEAR(shorter.max_abs_accel(), 4.0, 1e-12);
  expect_consistent(longer, 300);
  expect_continuous_acceleration(longer);
}

TEST(ScalarProfile, ShockChangesVelocityByDeltaWithItsPeak) {
  ScalarProfile p(0, 3.5);
  p.hold(0.1);
  p.shock(200.0, -3.5 * 1.3);  // end stop with restitution 0.3
  EXPECT_NEAR(p.end_state().v, -1.05, 1e-12);
  EXPECT_NEAR(p.max_abs_accel(), 200.0, 1e-9);
  EXPECT_LE(sampled_max_abs_accel(p), 200.0 + 1e-9);
  EXPECT_NEAR(p.end_s() - 0.1, 2 * 4.55 / 200, 1e-15);
  expect_consistent(p, 200);
  expect_continuous_acceleration(p);
}

TEST(ScalarProfile, JoltSwingsTheRateAndReturns) {
  ScalarProfile p(0, 10.0);
  p.jolt(800.0, 0.005);
  EXPECT_NEAR(p.end_state().v, 10.0, 1e-12);
  EXPECT_NEAR(p.max_abs_velocity(), 10.0 + 800.0 * 0.005 / 4, 1e-12);
  EXPECT_NEAR(p.max_abs_accel(), 800.0, 1e-9);
  EXPECT_LE(sampled_max_abs_accel(p), 800.0 + 1e-9);
  expect_consistent(p, 200);
  expect_continuous_acceleration(p);
}

TEST(ScalarProfile, ExtrapolatesAtConstantVelocityOutside) {
  ScalarProfile p(1.0, 0.0, 2.0);
  p.change_velocity(2.0, 10.0);
  EXPECT_DOUBLE_EQ(p.at(0.0).s, 1.0);
  const ProfileSample end = p.end_state();
  const ProfileSample later = p.at(p.end_s() + 3.0);
  EXPECT_NEAR(later.s, end.s + 6.0, 1e-12);
  EXPECT_DOUBLE_EQ(later.v, 2.0);
  EXPECT_DOUBLE_EQ(later.a, 0.0);
}

}  // namespace
}  // namespace tumble::sim
