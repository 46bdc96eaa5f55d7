// Trajectory: interpolation exact on a constant twist, constant-twist
// extrapolation at the ends, and the prefix-sum δ/θ equal to brute-force
// integration of the per-sample σ's.
#include "core/trajectory.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "core/speed_uncertainty.hpp"

namespace tumble {
namespace {

// Constant world velocity and constant body rate: p linear in t, q = q0 Exp(ω t).
struct ConstantTwist {
  Eigen::Vector3d p0{1.0, -2.0, 0.5};
  Eigen::Vector3d v_w{2.5, -1.0, 0.3};
  Eigen::Quaterniond q0 = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()));
  Eigen::Vector3d omega_l{0.7, -1.3, 9.0};

  Eigen::Quaterniond q(double t) const {
    return q0 * Eigen::Quaterniond(Eigen::AngleAxisd(omega_l.norm() * t, omega_l.normalized()));
  }
  Eigen::Vector3d p(double t) const { return p0 + v_w * t; }
  TrajectorySample sample(double t) const {
    TrajectorySample s;
    s.t_s = t;
    s.q_wl = q(t);
    s.p_w = p(t);
    s.v_w = v_w;
    s.omega_l = omega_l;
    return s;
  }
};

Trajectory constant_twist_trajectory(const ConstantTwist& twist, int samples, double dt) {
  Trajectory trajectory(4096, SpeedUncertaintyParams{});
  for (int i = 0; i < samples; ++i) trajectory.push_back(twist.sample(i * dt));
  return trajectory;
}

TEST(Trajectory, InterpolationIsExactOnAConstantTwist) {
  const ConstantTwist twist;
  const Trajectory trajectory = constant_twist_trajectory(twist, 101, 0.01);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> time(0.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const double t = time(rng);
    const Eigen::Isometry3d pose = trajectory.pose_at(t);
    EXPECT_LT((pose.translation() - twist.p(t)).norm(), 1e-12) << t;
    EXPECT_LT(Eigen::Quaterniond(pose.rotation()).angularDistance(twist.q(t)), 1e-9) << t;
  }
}

TEST(Trajectory, ExtrapolatesWithTheEndSampleTwist) {
  const ConstantTwist twist;
  const Trajectory trajectory = constant_twist_trajectory(twist, 11, 0.01);
  for (const double t : {-0.05, 0.1 + 0.03}) {
    const Eigen::Isometry3d pose = trajectory.pose_at(t);
    EXPECT_LT((pose.translation() - twist.p(t)).norm(), 1e-12) << t;
    EXPECT_LT(Eigen::Quaterniond(pose.rotation()).angularDistance(twist.q(t)), 1e-9) << t;
  }
}

TEST(Trajectory, VelocityIsLinearBetweenSamplesAndTheEndSamplesBeyond) {
  Trajectory trajectory(16, SpeedUncertaintyParams{});
  for (int i = 0; i <= 2; ++i) {
    TrajectorySample s;
    s.t_s = 0.1 * i;
    s.v_w = Eigen::Vector3d(1.0 * i, -2.0 * i, 0.5);
    trajectory.push_back(s);
  }
  EXPECT_LT((trajectory.velocity_at(0.05) - Eigen::Vector3d(0.5, -1.0, 0.5)).norm(), 1e-12);
  EXPECT_LT((trajectory.velocity_at(0.175) - Eigen::Vector3d(1.75, -3.5, 0.5)).norm(), 1e-12);
  EXPECT_EQ(trajectory.velocity_at(0.1), Eigen::Vector3d(1.0, -2.0, 0.5));  // at a sample: that sample's
  EXPECT_EQ(trajectory.velocity_at(-1.0), Eigen::Vector3d(0.0, 0.0, 0.5));
  EXPECT_EQ(trajectory.velocity_at(1.0), Eigen::Vector3d(2.0, -4.0, 0.5));
}

TEST(Trajectory, HintedLookupMatchesTheSearchFromAnyHint) {
  const ConstantTwist twist;
  const Trajectory trajectory = constant_twist_trajectory(twist, 101, 0.01);
  std::size_t hint = 57;
  for (const double t : {0.004, 0.005, 0.5, 0.2, 0.999, 0.31, 0.311, -1.0, 3.0, 0.0, 1.0}) {
    const Eigen::Isometry3d hinted = trajectory.pose_at(t, hint);
    EXPECT_TRUE(hinted.isApprox(trajectory.pose_at(t), 1e-14)) << t;
  }
  hint = 1'000'000;  // out of range is safe
  EXPECT_TRUE(trajectory.pose_at(0.42, hint).isApprox(trajectory.pose_at(0.42), 1e-14));
}

TEST(Trajectory, RelativePoseIsTheMotionBetweenTwoTimes) {
  const ConstantTwist twist;
  const Trajectory trajectory = constant_twist_trajectory(twist, 101, 0.01);
  const Eigen::Isometry3d relative = trajectory.relative_pose(0.2, 0.25);
  EXPECT_TRUE(relative.isApprox(trajectory.pose_at(0.2).inverse() * trajectory.pose_at(0.25), 1e-12));
  EXPECT_LT(Eigen::Quaterniond(relative.rotation()).angularDistance(twist.q(0.2).conjugate() * twist.q(0.25)), 1e-9);
}

// A trajectory whose speeds vary: v_w(t) and ω_L(t) sinusoidal, attitude spinning.
Trajectory varying_trajectory(const SpeedUncertaintyParams& params, std::vector<TrajectorySample>& samples) {
  Trajectory trajectory(4096, params);
  for (int i = 0; i <= 40; ++i) {
    TrajectorySample s;
    s.t_s = 10.0 + 0.01 * i + 0.002 * std::sin(i);  // uneven spacing
    s.q_wl = Eigen::Quaterniond(Eigen::AngleAxisd(3.0 * s.t_s, Eigen::Vector3d(0.2, 0.1, 1.0).normalized()));
    s.v_w = Eigen::Vector3d(3.0 * std::sin(5 * s.t_s), -1.0 + std::cos(3 * s.t_s), 0.5);
    s.omega_l = Eigen::Vector3d(std::sin(2 * s.t_s), 4.0 * std::cos(s.t_s), 12.0 + s.t_s);
    s.gyro_saturated[2] = (i % 7 == 3);
    s.accel_saturated[0] = (i % 11 == 5);
    samples.push_back(s);
    trajectory.push_back(s);
  }
  return trajectory;
}

// Brute force: the σ's evaluated at each sample from its lidar-frame speeds,
// linear in between, integrated with 2000 midpoint steps per segment.
SkewPerturbation brute_force_integral(const std::vector<TrajectorySample>& samples, double t_a, double t_b,
                                      bool deskewed, const SpeedUncertaintyParams& params) {
  auto sigmas = [&](const TrajectorySample& s) {
    const Eigen::Vector3d v_l = s.q_wl.conjugate() * s.v_w;
    SkewPerturbation rate;
    for (int k = 0; k < 3; ++k) {
      rate.delta_m[k] = linear_speed_sigma(v_l[k], s.accel_saturated[k], deskewed, params);
      rate.theta_rad[k] = angular_rate_sigma(s.omega_l[k], s.gyro_saturated[k], deskewed, params);
    }
    return rate;
  };
  SkewPerturbation sum;
  for (std::size_t i = 0; i + 1 < samples.size(); ++i) {
    const SkewPerturbation a = sigmas(samples[i]);
    const SkewPerturbation b = sigmas(samples[i + 1]);
    const double t0 = samples[i].t_s, t1 = samples[i + 1].t_s;
    const int steps = 2000;
    for (int k = 0; k < steps; ++k) {
      const double t = t0 + (k + 0.5) * (t1 - t0) / steps;
      if (t < t_a || t > t_b) continue;
      const double u = (t - t0) / (t1 - t0);
      const double dt = (t1 - t0) / steps;
      sum.delta_m += dt * ((1 - u) * a.delta_m + u * b.delta_m);
      sum.theta_rad += dt * ((1 - u) * a.theta_rad + u * b.theta_rad);
    }
  }
  return sum;
}

TEST(Trajectory, PrefixSumSkewIntegralsEqualBruteForceIntegration) {
  const SpeedUncertaintyParams params;
  std::vector<TrajectorySample> samples;
  const Trajectory trajectory = varying_trajectory(params, samples);
  // Bounds on the midpoint grid of the brute force (segment 3 step 500, segment 30 step 1500),
  // so the two agree to rounding.
  auto grid_time = [&](std::size_t segment, int step) {
    return samples[segment].t_s + step * (samples[segment + 1].t_s - samples[segment].t_s) / 2000.0;
  };
  const double t_a = grid_time(3, 500), t_b = grid_time(30, 1500);
  for (const bool deskewed : {false, true}) {
    const SkewPerturbation fast = trajectory.skew_integral(t_a, t_b, deskewed);
    const SkewPerturbation slow = brute_force_integral(samples, t_a, t_b, deskewed, params);
    EXPECT_LT((fast.delta_m - slow.delta_m).norm(), 1e-9 * (1 + slow.delta_m.norm())) << deskewed;
    EXPECT_LT((fast.theta_rad - slow.theta_rad).norm(), 1e-9 * (1 + slow.theta_rad.norm())) << deskewed;
    EXPECT_GT(slow.delta_m.minCoeff(), 0.0);
    EXPECT_GT(slow.theta_rad.minCoeff(), 0.0);
  }
}

TEST(Trajectory, SkewIntegratorPerPointMatchesTheDirectIntegral) {
  const SpeedUncertaintyParams params;
  std::vector<TrajectorySample> samples;
  const Trajectory trajectory = varying_trajectory(params, samples);
  const double t_start = 10.05;
  SkewIntegrator integrator(trajectory, t_start, true);
  for (double t = t_start; t < 10.5; t += 0.00037) {
    const SkewPerturbation per_point = integrator.until(t);
    const SkewPerturbation direct = trajectory.skew_integral(t_start, t, true);
    EXPECT_LT((per_point.delta_m - direct.delta_m).norm(), 1e-13);
    EXPECT_LT((per_point.theta_rad - direct.theta_rad).norm(), 1e-13);
  }
}

TEST(Trajectory, SaturatedGyroAxisIntegratesTheModelBound) {
  const SpeedUncertaintyParams params;
  Trajectory trajectory(16, params);
  for (int i = 0; i < 3; ++i) {
    TrajectorySample s;
    s.t_s = 0.01 * i;
    s.omega_l = Eigen::Vector3d(0, 0, 7.85);  // the gyro's clip value
    s.gyro_saturated[2] = true;
    trajectory.push_back(s);
  }
  const SkewPerturbation skew = trajectory.skew_integral(0.0, 0.02, true);
  EXPECT_NEAR(skew.theta_rad.z(), 0.02 * std::pow(11.0 / 16.0, 3), 1e-15);
  EXPECT_EQ(skew.theta_rad.x(), 0.0);
}

TEST(Trajectory, KeepsTheNewestSamplesAndRewritesItsTail) {
  const ConstantTwist twist;
  Trajectory ring(10, SpeedUncertaintyParams{});
  for (int i = 0; i < 15; ++i) ring.push_back(twist.sample(0.01 * i));
  EXPECT_EQ(ring.size(), 10u);
  EXPECT_DOUBLE_EQ(ring.t_begin_s(), 0.05);
  EXPECT_DOUBLE_EQ(ring.t_end_s(), 0.14);

  ring.truncate_after(0.105);
  EXPECT_DOUBLE_EQ(ring.t_end_s(), 0.10);
  TrajectorySample faster = twist.sample(0.11);
  faster.omega_l *= 2.0;
  ring.push_back(faster);
  // The rewritten tail integrates as if it had always been there.
  Trajectory fresh(10, SpeedUncertaintyParams{});
  for (int i = 5; i <= 10; ++i) fresh.push_back(twist.sample(0.01 * i));
  fresh.push_back(faster);
  const SkewPerturbation a = ring.skew_integral(0.06, 0.11, true);
  const SkewPerturbation b = fresh.skew_integral(0.06, 0.11, true);
  EXPECT_LT((a.theta_rad - b.theta_rad).norm(), 1e-15);
  EXPECT_LT((a.delta_m - b.delta_m).norm(), 1e-15);
}

TEST(Trajectory, RejectsTimesThatDoNotIncrease) {
  Trajectory trajectory(4, SpeedUncertaintyParams{});
  TrajectorySample s;
  s.t_s = 1.0;
  trajectory.push_back(s);
  EXPECT_THROW(trajectory.push_back(s), std::invalid_argument);
  EXPECT_THROW(Trajectory(4, SpeedUncertaintyParams{}).pose_at(0.0), std::logic_error);
}

}  // namespace
}  // namespace tumble
