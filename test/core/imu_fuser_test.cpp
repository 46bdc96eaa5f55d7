// The fuser against simulated IMU data with a known truth: static
// initialisation, the lever arm, the velocity filter (tracking a perfect lidar,
// removing a bias drift, applying the mean velocity at the mid-interval time),
// the pose correction, a translation the registration held, saturation flags,
// clipped gyro axes, the bounded buffers, IMU gaps, jumps and the restart
// at rest after a loss of track.
#include "core/imu_fuser.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace tumble {
namespace {

constexpr double kG = 9.80665;
constexpr double kT0 = 1000.0;         // first sample (absolute times, as in replay)
constexpr double kMotionStart = kT0 + 1.2;
constexpr double kDt = 0.01;           // 100 Hz
constexpr double kScanS = 0.1;         // a scan's first to last point (10 Hz)

// Motion of the IMU in W (z up); static before kMotionStart.
struct Truth {
  std::function<Eigen::Vector3d(double)> p_w = [](double) { return Eigen::Vector3d::Zero(); };
  std::function<Eigen::Vector3d(double)> v_w = [](double) { return Eigen::Vector3d::Zero(); };
  std::function<Eigen::Vector3d(double)> a_w = [](double) { return Eigen::Vector3d::Zero(); };
  std::function<Eigen::Quaterniond(double)> q_wi = [](double) { return Eigen::Quaterniond::Identity(); };
  std::function<Eigen::Vector3d(double)> omega_i = [](double) { return Eigen::Vector3d::Zero(); };
  std::function<Eigen::Vector3d(double)> accel_bias = [](double) { return Eigen::Vector3d::Zero(); };
};

ImuSample sample_at(const Truth& truth, double t) {
  ImuSample s;
  s.t_s = t;
  const Eigen::Quaterniond q = truth.q_wi(t);
  s.accel_m_s2 = q.conjugate() * (truth.a_w(t) + Eigen::Vector3d(0, 0, kG)) + truth.accel_bias(t);
  s.gyro_rad_s = truth.omega_i(t);
  s.has_orientation = true;
  s.orientation = q;
  return s;
}

double sample_time(int n) { return kT0 + kDt * n; }

// Feeds samples n_from..n_to inclusive.
void feed(ImuFuser& fuser, const Truth& truth, int n_from, int n_to) {
  for (int n = n_from; n <= n_to; ++n) fuser.add_imu(sample_at(truth, sample_time(n)));
}

ImuFuserParams device_attitude_params() {
  ImuFuserParams params;
  params.attitude_from_device = true;  // isolates the velocity filter from Madgwick's tilt under acceleration
  return params;
}

Eigen::Isometry3d pose_of(const Eigen::Quaterniond& q, const Eigen::Vector3d& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = p;
  return T;
}

// The registration of the scan that starts at t_scan_s and lasts kScanS;
// its attitude levels only by its position's expected error unless given.
CorrectionResult correct_scan(ImuFuser& fuser, double t_scan_s, const Eigen::Isometry3d& T_wl, double position_sigma_m,
                              bool map_start = false, double expected_error_m = 0.0,
                              double expected_rotation_error_rad = ScanCorrection{}.expected_rotation_error_rad) {
  return fuser.correct_with_registered_pose({.t_start_s = t_scan_s,
                                             .t_end_s = t_scan_s + kScanS,
                                             .T_wl = T_wl,
                                             .position_sigma_m = position_sigma_m,
                                             .map_start = map_start,
                                             .expected_error_m = expected_error_m,
                                             .expected_rotation_error_rad = expected_rotation_error_rad});
}

Eigen::Isometry3d at_pose(const Truth& truth, double t) { return pose_of(truth.q_wi(t), truth.p_w(t)); }

// Index of the last trajectory sample at or before t.
std::size_t sample_before(const Trajectory& trajectory, double t) {
  std::size_t i = 0;
  while (i + 1 < trajectory.size() && trajectory[i + 1].t_s <= t) ++i;
  return i;
}

TEST(ImuFuser, InitialisesLevelledFromAStaticPeriodAndEstimatesGyroBias) {
  Truth truth;
  const Eigen::Quaterniond tilted(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));
  truth.q_wi = [&](double) { return tilted; };
  const Eigen::Vector3d bias(0.01, -0.02, 0.005);
  truth.omega_i = [&](double) { return bias; };
  ImuFuserParams params;
  params.T_li.translation() = Eigen::Vector3d(0.1, 0.2, -0.3);
  ImuFuser fuser(params);
  feed(fuser, truth, 0, 99);
  EXPECT_FALSE(fuser.initialized());
  feed(fuser, truth, 100, 100);  // 1 s of static data
  ASSERT_TRUE(fuser.initialized());
  EXPECT_LT((fuser.gyro_bias_rad_s() - bias).norm(), 1e-12);
  EXPECT_NEAR(fuser.gravity_m_s2(), kG, 1e-9);

  const TrajectorySample& first = fuser.trajectory().front();
  EXPECT_DOUBLE_EQ(first.t_s, sample_time(100));
  EXPECT_LT(first.p_w.norm(), 1e-12);  // W's origin is the lidar
  // Levelled: the lidar's "up" is the measured one...
  const Eigen::Vector3d up_measured = (tilted.conjugate() * Eigen::Vector3d::UnitZ()).normalized();
  EXPECT_LT((first.q_wl.conjugate() * Eigen::Vector3d::UnitZ() - up_measured).norm(), 1e-12);
  // ...and the lidar's heading is W's x: its x axis has no W-y component.
  EXPECT_NEAR((first.q_wl * Eigen::Vector3d::UnitX()).y(), 0.0, 1e-12);
}

TEST(ImuFuser, KeepsWaitingWhileTheImuMoves) {
  Truth truth;
  truth.omega_i = [](double t) {
    return Eigen::Vector3d(0, 0, (t < kT0 + 1.995 || (t > kT0 + 2.505 && t < kT0 + 2.595)) ? 0.5 : 0.0);
  };
  ImuFuser fuser(ImuFuserParams{});
  feed(fuser, truth, 0, 199);
  EXPECT_FALSE(fuser.initialized());
  feed(fuser, truth, 200, 340);  // still 2.0–2.5, moving 2.5–2.6: the window restarts
  EXPECT_FALSE(fuser.initialized());
  EXPECT_EQ(fuser.stats().static_restarts, 1u);
  feed(fuser, truth, 341, 360);  // static again from 2.60: 1.0 s
  EXPECT_TRUE(fuser.initialized());
}

TEST(ImuFuser, PureRotationAboutTheImuGivesTheLidarOmegaCrossLeverArm) {
  const double rate = 2.0;
  Truth truth;
  truth.q_wi = [&](double t) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(rate * std::max(0.0, t - kMotionStart), Eigen::Vector3d::UnitZ()));
  };
  truth.omega_i = [&](double t) { return Eigen::Vector3d(0, 0, t > kMotionStart ? rate : 0.0); };
  ImuFuserParams params;  // Madgwick attitude
  params.T_li.translation() = Eigen::Vector3d(-0.3, 0.0, -0.1);  // IMU seen from the lidar
  const Eigen::Vector3d r_il(0.3, 0.0, 0.1);                      // lidar seen from the IMU
  ImuFuser fuser(params);
  feed(fuser, truth, 0, 300);
  const TrajectorySample& s = fuser.trajectory().back();
  const Eigen::Quaterniond q = truth.q_wi(s.t_s);
  EXPECT_LT((s.v_w - q * Eigen::Vector3d(0, 0, rate).cross(r_il)).norm(), 1e-9);
  EXPECT_NEAR(s.v_w.norm(), rate * 0.3, 1e-9);
  EXPECT_LT((s.p_w - (Eigen::Vector3d(-0.3, 0.0, -0.1) + q * r_il)).norm(), 1e-9);  // on the circle
  EXPECT_LT((s.omega_l - Eigen::Vector3d(0, 0, rate)).norm(), 1e-12);
}

// Tilt between the fuser's attitude and the truth's at trajectory sample i, in rad.
double tilt_error_rad(const ImuFuser& fuser, const Truth& truth, std::size_t i) {
  const TrajectorySample& s = fuser.trajectory()[i];
  const Eigen::Vector3d up_estimated = s.q_wl.conjugate() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d up_true = truth.q_wi(s.t_s).conjugate() * Eigen::Vector3d::UnitZ();
  return std::atan2(up_estimated.cross(up_true).norm(), up_estimated.dot(up_true));
}

double largest_tilt_error_after_rad(const ImuFuser& fuser, const Truth& truth, double t_s) {
  double largest = 0.0;
  for (std::size_t i = 0; i < fuser.trajectory().size(); ++i) {
    if (fuser.trajectory()[i].t_s > t_s) largest = std::max(largest, tilt_error_rad(fuser, truth, i));
  }
  return largest;
}

TEST(ImuFuser, ATurntablesCentripetalAccelerationDoesNotTiltAnAttitudeTheRegistrationsLevel) {
  // An IMU 0.1 m off the axis at 4 rad/s (bench turntable-26): 1.6 m/s²
  // towards the axis, which the 2 m/s² gate lets through, so the
  // accelerometer's "up" leans 9.3° inwards for as long as the spin lasts.
  const double rate = 4.0, radius = 0.1;
  auto angle = [&](double t) { return rate * std::max(0.0, t - kMotionStart); };
  Truth truth;
  truth.q_wi = [&](double t) { return Eigen::Quaterniond(Eigen::AngleAxisd(angle(t), Eigen::Vector3d::UnitZ())); };
  truth.omega_i = [&](double t) { return Eigen::Vector3d(0, 0, t > kMotionStart ? rate : 0.0); };
  truth.p_w = [&](double t) { return (radius * Eigen::Vector3d(std::cos(angle(t)) - 1.0, std::sin(angle(t)), 0.0)).eval(); };
  truth.a_w = [&](double t) {
    if (t <= kMotionStart) return Eigen::Vector3d::Zero().eval();
    return (-rate * rate * radius * Eigen::Vector3d(std::cos(angle(t)), std::sin(angle(t)), 0.0)).eval();
  };
  ImuFuser ours(ImuFuserParams{});
  ImuFuserParams paper_params;
  paper_params.accel_correction_after_s = 0.0;  // Madgwick's step on every sample
  ImuFuser paper(paper_params);
  for (ImuFuser* fuser : {&ours, &paper}) {
    feed(*fuser, truth, 0, 120);
    // A scan every 0.1 s, registered at the true pose once the IMU covers it.
    for (int scan = 0; scan < 10; ++scan) {
      const int first = 120 + 10 * scan;
      feed(*fuser, truth, first + 1, first + 10);
      const double t_scan = sample_time(first) + 0.005;
      correct_scan(*fuser, t_scan, pose_of(truth.q_wi(t_scan), truth.p_w(t_scan)), 0.01);
    }
    ASSERT_TRUE(fuser->initialized());
  }
  // The gyro alone keeps the level each registration gives it...
  EXPECT_LT(largest_tilt_error_after_rad(ours, truth, kMotionStart), 1e-6);
  // ...the accelerometer's step leans it by β·dt per sample until the next
  // one: 0.57° (0.01 rad) over a scan.
  EXPECT_GT(largest_tilt_error_after_rad(paper, truth, kMotionStart), 0.005);
}

TEST(ImuFuser, WithoutRegistrationsOnAMapTheAccelerometerLevelsTheAttitude) {
  // At rest and level; a correction then tilts the attitude by 3°.
  const Truth truth;
  const Eigen::Quaterniond tilted(Eigen::AngleAxisd(0.0524, Eigen::Vector3d::UnitX()));
  struct Case {
    const char* what;
    bool map_start;
    double expected_error_m;
    double expected_rotation_error_rad;
    bool levels;
  };
  const double inf = std::numeric_limits<double>::infinity();
  for (const Case& c : {Case{"a scan registered on a map", false, 0.01, inf, true},
                        Case{"a map's first scan (the prediction itself)", true, 0.0, 0.0, false},
                        Case{"a weakly constrained scan", false, 0.05, inf, false},
                        Case{"a corridor's scan: the position weak, the attitude pinned", false, 1.0, 0.0015, true},
                        Case{"a scan weak in attitude too", false, 0.05, 0.004, false}}) {
    SCOPED_TRACE(c.what);
    ImuFuser fuser(ImuFuserParams{});
    feed(fuser, truth, 0, 150);
    correct_scan(fuser, sample_time(150) - 0.005, pose_of(tilted, Eigen::Vector3d::Zero()), 0.01, c.map_start,
                 c.expected_error_m, c.expected_rotation_error_rad);
    feed(fuser, truth, 151, 190);  // 0.4 s
    const double tilt_at_0_4_s = tilt_error_rad(fuser, truth, fuser.trajectory().size() - 1);
    feed(fuser, truth, 191, 300);  // 1.5 s
    const double tilt_at_1_5_s = tilt_error_rad(fuser, truth, fuser.trajectory().size() - 1);
    if (c.levels) {
      // Within accel_correction_after_s of a registration, the gyro alone.
      EXPECT_NEAR(tilt_at_0_4_s, 0.0524, 1e-6);
    } else {
      // Nothing levels it but the accelerometer, at β = 0.1 rad/s.
      EXPECT_LT(tilt_at_0_4_s, 0.02);
    }
    EXPECT_LT(tilt_at_1_5_s, 1e-3);
  }
}

// A smooth 3-D motion from rest with a slow yaw, and an accelerometer bias.
Truth wandering_motion(const Eigen::Vector3d& accel_bias) {
  Truth truth;
  const Eigen::Vector3d amplitude(2.0, 1.0, 0.3);
  const double w = 1.5, yaw_rate = 0.3;
  auto tau = [](double t) { return std::max(0.0, t - kMotionStart); };
  truth.p_w = [=](double t) { return Eigen::Vector3d(amplitude * (1 - std::cos(w * tau(t)))); };
  truth.v_w = [=](double t) { return Eigen::Vector3d(amplitude * w * std::sin(w * tau(t))); };
  truth.a_w = [=](double t) -> Eigen::Vector3d {
    return t > kMotionStart ? Eigen::Vector3d(amplitude * w * w * std::cos(w * tau(t))) : Eigen::Vector3d::Zero();
  };
  truth.q_wi = [=](double t) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(yaw_rate * tau(t), Eigen::Vector3d::UnitZ()));
  };
  truth.omega_i = [=](double t) { return Eigen::Vector3d(0, 0, t > kMotionStart ? yaw_rate : 0.0); };
  truth.accel_bias = [=](double t) -> Eigen::Vector3d {
    return t > kMotionStart ? accel_bias : Eigen::Vector3d::Zero();
  };
  return truth;
}

TEST(ImuFuser, ACorrectionGivesTheSameTrajectoryWhicheverSamplesArriveBeforeIt) {
  // Live, a scan's registration reaches the fuser some IMU samples after the
  // scan ends: how many depends on thread timing (a lossless replay holds
  // the fuser at the first sample past the scan's end). Each scan is
  // registered 0.3 mm and 0.05° off the truth, so every correction moves the
  // estimate; the gyro and the accelerometer clip, and the accelerometer
  // levels for a while, so every way of stepping the attitude is taken again.
  Truth truth = wandering_motion(Eigen::Vector3d(0.1, -0.05, 0.02));
  // A yaw of 0.3 rad/s, and of 9 rad/s (above the gyro's range) 0.5-0.8 s
  // into the motion (the gyro alone carries the attitude) and 1.5-1.9 s
  // (the accelerometer levels it).
  auto tau = [](double t) { return std::max(0.0, t - kMotionStart); };
  truth.q_wi = [=](double t) {
    const double fast_s = std::clamp(tau(t) - 0.5, 0.0, 0.3) + std::clamp(tau(t) - 1.5, 0.0, 0.4);
    return Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * tau(t) + 8.7 * fast_s, Eigen::Vector3d::UnitZ()));
  };
  truth.omega_i = [=](double t) {
    const bool fast = (tau(t) > 0.5 && tau(t) <= 0.8) || (tau(t) > 1.5 && tau(t) <= 1.9);
    return Eigen::Vector3d(0, 0, t > kMotionStart ? (fast ? 9.0 : 0.3) : 0.0);
  };
  const Eigen::Quaterniond offset(Eigen::AngleAxisd(0.0009, Eigen::Vector3d(1, 2, 3).normalized()));
  auto sample = [&](int n) {
    ImuSample s = sample_at(truth, sample_time(n));
    for (int k = 0; k < 3; ++k) {
      s.gyro_saturated[k] = std::abs(s.gyro_rad_s[k]) > 7.85;
      if (s.gyro_saturated[k]) s.gyro_rad_s[k] = std::copysign(7.85, s.gyro_rad_s[k]);
      s.accel_saturated[k] = std::abs(s.accel_m_s2[k]) > 3.0 && k != 2;
      if (s.accel_saturated[k]) s.accel_m_s2[k] = std::copysign(3.0, s.accel_m_s2[k]);
    }
    return s;
  };
  // The trajectory each scan's registration reads (its span, before its own
  // correction), then the whole trajectory at the end.
  auto run = [&](int samples_before_correction) {
    std::vector<std::vector<TrajectorySample>> seen;
    ImuFuser fuser(ImuFuserParams{});
    int fed = -1;
    auto feed_to = [&](int n) {
      for (; fed < n; ++fed) fuser.add_imu(sample(fed + 1));
    };
    feed_to(120);
    for (int scan = 0; scan < 30; ++scan) {
      const int first = 120 + 10 * scan;
      feed_to(first + 10 + samples_before_correction);
      const double t_scan = sample_time(first) + 0.005;
      // Scans 10-19 are weakly constrained: they do not level, so from 0.5 s
      // after scan 9 the accelerometer steps the attitude again.
      const double expected_error_m = scan >= 10 && scan < 20 ? 0.1 : 0.0;
      std::vector<TrajectorySample>& read = seen.emplace_back();
      for (std::size_t i = 0; i < fuser.trajectory().size(); ++i)
        if (fuser.trajectory()[i].t_s >= t_scan && fuser.trajectory()[i].t_s <= t_scan + kScanS)
          read.push_back(fuser.trajectory()[i]);
      correct_scan(fuser, t_scan,
                   pose_of(offset * truth.q_wi(t_scan), truth.p_w(t_scan) + Eigen::Vector3d(3e-4, 0, 0)), 0.01,
                   false, expected_error_m);
    }
    feed_to(120 + 10 * 30 + 20);
    EXPECT_GT(fuser.stats().accel_saturated_samples, 0u);
    EXPECT_GT(fuser.stats().gyro_samples_from_lidar, 0u);
    std::vector<TrajectorySample>& whole = seen.emplace_back();
    for (std::size_t i = 0; i < fuser.trajectory().size(); ++i) whole.push_back(fuser.trajectory()[i]);
    return seen;
  };
  const auto lossless = run(1);  // held at the first sample past each scan's end
  for (const int late : {2, 5, 9}) {
    const auto later = run(late);
    ASSERT_EQ(later.size(), lossless.size());
    for (std::size_t k = 0; k < later.size(); ++k) {
      SCOPED_TRACE(::testing::Message() << late << " samples late, "
                                        << (k + 1 < later.size() ? "what scan " + std::to_string(k) + " read"
                                                                 : std::string("the whole trajectory")));
      ASSERT_EQ(later[k].size(), lossless[k].size());
      for (std::size_t i = 0; i < later[k].size(); ++i) {
        ASSERT_EQ(later[k][i].t_s, lossless[k][i].t_s) << i;
        ASSERT_EQ(later[k][i].p_w, lossless[k][i].p_w) << i;
        ASSERT_EQ(later[k][i].q_wl.coeffs(), lossless[k][i].q_wl.coeffs()) << i;
        ASSERT_EQ(later[k][i].v_w, lossless[k][i].v_w) << i;
      }
    }
  }
}

TEST(ImuFuser, VelocityFilterTracksAPerfectLidarAndRemovesABiasDrift) {
  const Truth truth = wandering_motion(Eigen::Vector3d(0.2, 0.0, 0.0));
  ImuFuser corrected(device_attitude_params());
  ImuFuser drifting(device_attitude_params());
  feed(corrected, truth, 0, 130);
  feed(drifting, truth, 0, 1130);
  // Scans every 0.1 s, starting between IMU samples; each registered once the
  // IMU covers the scan (as the pipeline does).
  for (int scan = 0; scan < 100; ++scan) {
    const int n_start = 130 + 10 * scan;
    feed(corrected, truth, n_start + 1, n_start + 10);
    const double t_scan = sample_time(n_start) - 0.004;
    const CorrectionResult result =
        correct_scan(corrected, t_scan, pose_of(truth.q_wi(t_scan), truth.p_w(t_scan)), 0.002);
    ASSERT_TRUE(result.pose_reset);
    ASSERT_EQ(result.velocity_updated, scan > 0);
  }
  const double t_end = corrected.trajectory().t_end_s();
  ASSERT_DOUBLE_EQ(t_end, drifting.trajectory().t_end_s());
  const Eigen::Vector3d v_true = truth.v_w(t_end);
  const double corrected_error = (corrected.trajectory().back().v_w - v_true).norm();
  const double drift_error = (drifting.trajectory().back().v_w - v_true).norm();
  EXPECT_GT(drift_error, 1.0);  // 0.2 m/s² over 10 s, turning with the yaw
  EXPECT_LT(corrected_error, 0.05);
  EXPECT_LT((corrected.trajectory().back().p_w - truth.p_w(t_end)).norm(), 0.01);
  EXPECT_EQ(corrected.stats().velocity_updates, 99u);
}

TEST(ImuFuser, LidarMeanVelocityIsAppliedAtTheMidIntervalTime) {
  // Constant acceleration along x. The accelerometer reads 0.5 m/s² too much for
  // the first second, which leaves the filter 0.5 m/s fast; then it is exact.
  const double accel = 3.0;
  Truth truth;
  auto tau = [](double t) { return std::max(0.0, t - kMotionStart); };
  truth.p_w = [&](double t) { return Eigen::Vector3d(0.5 * accel * tau(t) * tau(t), 0, 0); };
  truth.v_w = [&](double t) { return Eigen::Vector3d(accel * tau(t), 0, 0); };
  truth.a_w = [&](double t) { return Eigen::Vector3d(t > kMotionStart ? accel : 0.0, 0, 0); };
  truth.accel_bias = [&](double t) {
    return Eigen::Vector3d(tau(t) > 0.0 && tau(t) <= 1.0 ? 0.5 : 0.0, 0, 0);
  };
  ImuFuser fuser(device_attitude_params());
  const double t_previous = kMotionStart + 1.203;  // scan starts between samples
  const double t_scan = t_previous + 0.1;
  const double t_mid = 0.5 * (t_previous + t_scan);  // kMotionStart + 1.253
  feed(fuser, truth, 0, 255);                          // to t_previous + 0.1
  correct_scan(fuser, t_previous, pose_of(truth.q_wi(t_previous), truth.p_w(t_previous)), 1e-6);
  feed(fuser, truth, 256, 265);                        // to t_scan + 0.1
  const std::size_t before_mid = sample_before(fuser.trajectory(), t_mid);
  const TrajectorySample& last_before_mid = fuser.trajectory()[before_mid];
  const double error_before = last_before_mid.v_w.x() - truth.v_w(last_before_mid.t_s).x();
  // 0.5 from the bias, less 0.015 lost by the trapezoid at the acceleration's onset.
  ASSERT_NEAR(error_before, 0.485, 1e-6);

  const CorrectionResult result =
      correct_scan(fuser, t_scan, pose_of(truth.q_wi(t_scan), truth.p_w(t_scan)), 1e-6);
  ASSERT_TRUE(result.velocity_updated);
  EXPECT_LT(result.rewritten_after_s, t_mid);
  const Trajectory& trajectory = fuser.trajectory();
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const TrajectorySample& s = trajectory[i];
    if (s.t_s < t_previous) continue;
    const double error = s.v_w.x() - truth.v_w(s.t_s).x();
    if (s.t_s < t_mid) {
      EXPECT_NEAR(error, 0.485, 1e-6) << "before the measurement's time: untouched, t = " << s.t_s;
    } else {
      EXPECT_NEAR(error, 0.0, 1e-6) << "after it: corrected, t = " << s.t_s;
    }
  }
  // Why the middle: the lidar velocity is the interval's mean, which equals the
  // velocity at t_mid only; taken as the velocity at the scan time it would be
  // a·Δt/2 = 0.15 m/s off.
  const double lidar_mean = (truth.p_w(t_scan) - truth.p_w(t_previous)).x() / 0.1;
  EXPECT_NEAR(truth.v_w(t_scan).x() - lidar_mean, 0.15, 1e-9);
  EXPECT_NEAR(trajectory.back().v_w.x(), truth.v_w(trajectory.back().t_s).x(), 1e-6);
}

// At rest, but the accelerometer reads 0.5 m/s² too much along x and y for
// a second from kMotionStart: the filter believes 0.5 m/s along both.
Truth at_rest_with_a_second_of_accel_bias() {
  Truth truth;
  truth.accel_bias = [](double t) {
    const double tau = t - kMotionStart;
    return tau > 0.0 && tau <= 1.0 ? Eigen::Vector3d(0.5, 0.5, 0.0) : Eigen::Vector3d::Zero();
  };
  return truth;
}

TEST(ImuFuser, AScanThatHeldATranslationDoesNotMeasureTheVelocityAlongIt) {
  // The next scan held its translation along x at the prediction (a
  // corridor's axis), so its velocity measurement says nothing there.
  const Truth truth = at_rest_with_a_second_of_accel_bias();
  ImuFuser fuser(device_attitude_params());
  const double t_previous = kMotionStart + 1.203;
  const double t_scan = t_previous + 0.1;
  const Eigen::Isometry3d at_rest = pose_of(Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero());
  feed(fuser, truth, 0, 255);
  correct_scan(fuser, t_previous, at_rest, 1e-6);
  feed(fuser, truth, 256, 265);
  const Eigen::Vector3d v_before = fuser.trajectory().back().v_w;
  const Eigen::Vector3d variance_before = fuser.velocity_variance();
  ASSERT_GT(v_before.x(), 0.4);
  ASSERT_GT(v_before.y(), 0.4);
  const CorrectionResult result = fuser.correct_with_registered_pose({.t_start_s = t_scan,
                                                                      .t_end_s = t_scan + kScanS,
                                                                      .T_wl = at_rest,
                                                                      .position_sigma_m = 1e-6,
                                                                      .unmeasured_w = Eigen::Vector3d::UnitX()});
  ASSERT_TRUE(result.velocity_updated);
  const Eigen::Vector3d v_after = fuser.trajectory().back().v_w;
  EXPECT_NEAR(v_after.y(), 0.0, 1e-3);             // measured: corrected
  EXPECT_NEAR(v_after.x(), v_before.x(), 1e-3);  // held: the IMU's, as it was
  // Nor does it make the filter surer of the velocity there.
  EXPECT_NEAR(fuser.velocity_variance().x(), variance_before.x(), 1e-5);
  EXPECT_LT(fuser.velocity_variance().y(), 0.2 * variance_before.y());
}

TEST(ImuFuser, ConsistentCorrectionLeavesTheTrajectoryUnchanged) {
  // Constant velocity: the fuser's own poses are exact, so re-propagation with a
  // zero innovation and no offset must reproduce the forward integration.
  Truth truth;
  truth.p_w = [](double t) -> Eigen::Vector3d {
    return Eigen::Vector3d(0.3, -0.2, 0.1) * std::max(0.0, t - kMotionStart);
  };
  truth.v_w = [](double t) -> Eigen::Vector3d {
    return t > kMotionStart ? Eigen::Vector3d(0.3, -0.2, 0.1) : Eigen::Vector3d::Zero();
  };
  ImuFuser fuser(device_attitude_params());
  feed(fuser, truth, 0, 119);
  // Kick the filter to the true velocity with one exact pair of corrections.
  feed(fuser, truth, 120, 160);
  for (const double t : {kMotionStart + 0.203, kMotionStart + 0.303}) {
    correct_scan(fuser, t, pose_of(Eigen::Quaterniond::Identity(), truth.p_w(t)), 1e-9);
  }
  feed(fuser, truth, 161, 200);
  const Trajectory before = fuser.trajectory();
  const double t_scan = kMotionStart + 0.403;
  const Eigen::Isometry3d fused = before.pose_at(t_scan);
  const CorrectionResult result = correct_scan(fuser, t_scan, fused, 0.01);
  ASSERT_TRUE(result.velocity_updated);
  const Trajectory& after = fuser.trajectory();
  ASSERT_EQ(after.size(), before.size() + 1);  // plus the registered pose at t_scan
  for (std::size_t i = 0; i < after.size(); ++i) {
    const Eigen::Isometry3d expected = before.pose_at(after[i].t_s);
    EXPECT_LT((after[i].p_w - expected.translation()).norm(), 1e-9) << i;
    EXPECT_LT(after[i].q_wl.angularDistance(Eigen::Quaterniond(expected.rotation())), 1e-12) << i;
    if (after[i].t_s > kMotionStart + 0.253) {  // after the kick's velocity update
      EXPECT_LT((after[i].v_w - truth.v_w(after[i].t_s)).norm(), 1e-9) << i;
    }
  }
}

TEST(ImuFuser, PoseCorrectionReanchorsAtTheScanStartWithoutLaterJumps) {
  const Truth truth = wandering_motion(Eigen::Vector3d(0.3, -0.2, 0.0));  // drifting fuser
  ImuFuser fuser(device_attitude_params());
  feed(fuser, truth, 0, 350);
  const Trajectory before = fuser.trajectory();
  const double t_scan = sample_time(330) + 0.0042;
  // The registration's pose: the truth, turned by 0.2 rad of yaw, 1.5 m away from the fused one.
  const Eigen::Quaterniond q_registered =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ())) * truth.q_wi(t_scan);
  const Eigen::Isometry3d registered = pose_of(q_registered, truth.p_w(t_scan));
  ASSERT_GT((registered.translation() - before.pose_at(t_scan).translation()).norm(), 0.05);
  correct_scan(fuser, t_scan, registered, 0.01);
  const Trajectory& after = fuser.trajectory();

  // Through the registered pose at the scan start...
  const Eigen::Isometry3d at_scan = after.pose_at(t_scan);
  EXPECT_LT((at_scan.translation() - registered.translation()).norm(), 1e-9);
  EXPECT_LT(Eigen::Quaterniond(at_scan.rotation()).angularDistance(q_registered), 1e-9);
  // ...untouched before it...
  const std::size_t last_before = sample_before(before, t_scan);
  for (std::size_t i = 0; i <= last_before; ++i) EXPECT_EQ(after[i].p_w, before[i].p_w);
  // ...and continuous after it (from the sample the fuser adds at t_scan): each
  // step moves by its mean velocity, and the attitude keeps the gyro's
  // relative rotation.
  ASSERT_DOUBLE_EQ(after[last_before + 1].t_s, t_scan);
  for (std::size_t i = last_before + 1; i + 1 < after.size(); ++i) {
    const double dt = after[i + 1].t_s - after[i].t_s;
    const Eigen::Vector3d step = after[i + 1].p_w - after[i].p_w;
    EXPECT_LT((step - 0.5 * dt * (after[i].v_w + after[i + 1].v_w)).norm(), 1e-9) << i;
    const Eigen::Quaterniond relative_after = after[i].q_wl.conjugate() * after[i + 1].q_wl;
    const Eigen::Quaterniond relative_before(
        (before.pose_at(after[i].t_s).inverse() * before.pose_at(after[i + 1].t_s)).rotation());
    EXPECT_LT(relative_after.angularDistance(relative_before), 1e-9) << i;
  }
}

TEST(ImuFuser, SaturationIsFlaggedPerLidarAxisAndAccelClipsLastUntilTheNextVelocityUpdate) {
  Truth truth;
  ImuFuserParams params = device_attitude_params();
  // Lidar turned +90° about x from the IMU: IMU z is lidar −y.
  params.T_li.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  ImuFuser fuser(params);
  feed(fuser, truth, 0, 150);
  ImuSample clipped = sample_at(truth, sample_time(151));
  clipped.gyro_saturated[2] = true;
  fuser.add_imu(clipped);
  const TrajectorySample& gyro_flagged = fuser.trajectory().back();
  EXPECT_EQ(gyro_flagged.gyro_saturated, (std::array<bool, 3>{false, true, false}));
  EXPECT_EQ(gyro_flagged.saturated, (std::array<bool, 3>{false, true, false}));

  const double variance_before = fuser.velocity_variance().x();
  clipped = sample_at(truth, sample_time(152));
  clipped.accel_saturated[0] = true;  // IMU x = lidar x = W x (level, no yaw)
  fuser.add_imu(clipped);
  // (saturated_accel_sigma · dt)² = 1 (m/s)², plus one step of process noise.
  EXPECT_NEAR(fuser.velocity_variance().x() - variance_before, std::pow(100.0 * kDt, 2), 2e-4);
  feed(fuser, truth, 153, 170);
  // The integrated speed stays unknown on the following (unclipped) samples.
  EXPECT_EQ(fuser.trajectory().back().accel_saturated, (std::array<bool, 3>{true, false, false}));
  EXPECT_FALSE(fuser.trajectory().back().gyro_saturated[1]);
  EXPECT_EQ(fuser.stats().accel_saturated_samples, 1u);

  // Two registered poses: the velocity update at their mid time clears it.
  feed(fuser, truth, 171, 400);
  for (const int n : {250, 260}) {
    const double t = sample_time(n);
    correct_scan(fuser, t, fuser.trajectory().pose_at(t), 0.01);
  }
  const Trajectory& trajectory = fuser.trajectory();
  EXPECT_TRUE(trajectory[sample_before(trajectory, sample_time(254))].accel_saturated[0]);
  EXPECT_FALSE(trajectory[sample_before(trajectory, sample_time(256))].accel_saturated[0]);
  EXPECT_FALSE(trajectory.back().saturated[0]);
}

TEST(ImuFuser, TheScanAfterAHeldOneDoesNotPassTheHeldDriftIntoTheVelocity) {
  // At rest. A scan held x at a prediction 10 cm off (drifted); the next one
  // measures x again at the truth. The interval between them starts from a
  // prediction along x: taken as measured, its 10 cm would be 1 m/s.
  Truth truth;
  ImuFuser fuser(device_attitude_params());
  feed(fuser, truth, 0, 400);
  const Eigen::Isometry3d at_rest = pose_of(Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero());
  correct_scan(fuser, sample_time(250), at_rest, 0.01);
  const double t_held = sample_time(260);
  fuser.correct_with_registered_pose({.t_start_s = t_held,
                                      .t_end_s = t_held + kScanS,
                                      .T_wl = pose_of(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1, 0, 0)),
                                      .position_sigma_m = 0.01,
                                      .unmeasured_w = Eigen::Vector3d::UnitX()});
  correct_scan(fuser, sample_time(270), at_rest, 0.01);
  EXPECT_LT(std::abs(fuser.trajectory().back().v_w.x()), 0.01);
}

TEST(ImuFuser, AClippedAxisStaysUnknownThroughAScanThatHeldItsTranslation) {
  Truth truth;  // at rest
  ImuFuser fuser(device_attitude_params());
  feed(fuser, truth, 0, 150);
  ImuSample clipped = sample_at(truth, sample_time(151));
  clipped.accel_saturated[0] = true;
  clipped.accel_saturated[1] = true;
  fuser.add_imu(clipped);
  feed(fuser, truth, 152, 400);
  correct_scan(fuser, sample_time(250), fuser.trajectory().pose_at(sample_time(250)), 0.01);
  const double t_held = sample_time(260);
  fuser.correct_with_registered_pose({.t_start_s = t_held,
                                      .t_end_s = t_held + kScanS,
                                      .T_wl = fuser.trajectory().pose_at(t_held),
                                      .position_sigma_m = 0.01,
                                      .unmeasured_w = Eigen::Vector3d::UnitX()});
  // The update at the mid time (2.55 s) measured y, not x.
  const Trajectory& trajectory = fuser.trajectory();
  EXPECT_EQ(trajectory[sample_before(trajectory, sample_time(258))].accel_saturated,
            (std::array<bool, 3>{true, false, false}));
  // The next interval starts at the held scan: x still unmeasured.
  correct_scan(fuser, sample_time(270), fuser.trajectory().pose_at(sample_time(270)), 0.01);
  EXPECT_TRUE(trajectory[sample_before(trajectory, sample_time(268))].accel_saturated[0]);
  correct_scan(fuser, sample_time(280), fuser.trajectory().pose_at(sample_time(280)), 0.01);
  EXPECT_EQ(trajectory[sample_before(trajectory, sample_time(278))].accel_saturated,
            (std::array<bool, 3>{false, false, false}));
}

// A yaw at `rate` from kMotionStart whose gyro reads (and flags) clipped_rate.
struct ClippedYaw {
  Truth truth;
  double clipped_rate = 0.0;
  ImuSample sample(int n) const {
    ImuSample s = sample_at(truth, sample_time(n));
    if (std::abs(s.gyro_rad_s.z()) > clipped_rate) {
      s.gyro_rad_s.z() = std::copysign(clipped_rate, s.gyro_rad_s.z());
      s.gyro_saturated[2] = true;
    }
    return s;
  }
};

ClippedYaw clipped_yaw(double rate, double clipped_rate) {
  ClippedYaw yaw;
  yaw.clipped_rate = clipped_rate;
  yaw.truth.q_wi = [=](double t) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(rate * std::max(0.0, t - kMotionStart), Eigen::Vector3d::UnitZ()));
  };
  yaw.truth.omega_i = [=](double t) { return Eigen::Vector3d(0, 0, t > kMotionStart ? rate : 0.0); };
  return yaw;
}

double angle_deg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return Eigen::AngleAxisd(a.conjugate() * b).angle() * 180.0 / std::numbers::pi;
}

// Feeds the scans of 10 samples from sample 200 on, each registered with the
// true pose half a scan after it ends (the pipeline's lag); `registered_q`
// gives the registered attitude. Returns the newest trajectory sample's error.
double run_scans(ImuFuser& fuser, const ClippedYaw& yaw,
                 const std::function<Eigen::Quaterniond(double)>& registered_q, int scans) {
  for (int n = 0; n < 200; ++n) fuser.add_imu(yaw.sample(n));
  int fed = 199;
  for (int k = 0; k < scans; ++k) {
    const int scan_start = 200 + 10 * k;
    for (; fed < scan_start + 15; ++fed) fuser.add_imu(yaw.sample(fed + 1));
    const double t = sample_time(scan_start);
    correct_scan(fuser, t, pose_of(registered_q(t), Eigen::Vector3d::Zero()), 0.01);
  }
  const TrajectorySample& newest = fuser.trajectory().back();
  return angle_deg(newest.q_wl, yaw.truth.q_wi(newest.t_s));
}

TEST(ImuFuser, AClippedGyroAxisTakesTheLidarRateAndTheAttitudeKeepsUp) {
  // 10 rad/s against the MTi-30's 7.85 rad/s range: 2.15 rad/s missing, 6.2°
  // over the 0.05 s the newest samples run ahead of the last registered scan.
  const ClippedYaw yaw = clipped_yaw(10.0, 7.85);
  ImuFuser with_lidar_rate(ImuFuserParams{});
  const double error_deg = run_scans(with_lidar_rate, yaw, yaw.truth.q_wi, 20);
  EXPECT_LT(error_deg, 0.2);
  EXPECT_GT(with_lidar_rate.stats().gyro_samples_from_lidar, 100u);
  EXPECT_TRUE(with_lidar_rate.trajectory().back().gyro_saturated[2]);  // still flagged for the weights
  EXPECT_NEAR(with_lidar_rate.trajectory().back().omega_l.z(), 10.0, 1e-6);

  // Control: corrections with one scan only (no lidar rate yet) leave the clip.
  ImuFuser single_scan(ImuFuserParams{});
  EXPECT_GT(run_scans(single_scan, yaw, yaw.truth.q_wi, 1), 5.0);
  EXPECT_EQ(single_scan.stats().gyro_samples_from_lidar, 0u);
}

TEST(ImuFuser, TheClippedReadingStaysALowerBoundOnTheRate) {
  // The registration claims 5 rad/s while the gyro is clipped at 7.85: the
  // gyro is right that it turns at least that fast, so its value is kept.
  const ClippedYaw yaw = clipped_yaw(10.0, 7.85);
  ImuFuser fuser(ImuFuserParams{});
  const auto slow = [](double t) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(5.0 * std::max(0.0, t - kMotionStart), Eigen::Vector3d::UnitZ()));
  };
  run_scans(fuser, yaw, slow, 10);
  EXPECT_EQ(fuser.stats().gyro_samples_from_lidar, 0u);
  EXPECT_NEAR(fuser.trajectory().back().omega_l.z(), 7.85, 1e-6);
}

TEST(ImuFuser, RejectsCorrectionsItCannotPlaceAndOutOfOrderSamples) {
  Truth truth;
  ImuFuser fuser(ImuFuserParams{});
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  EXPECT_FALSE(correct_scan(fuser, kT0, identity, 0.01).pose_reset);
  EXPECT_EQ(fuser.stats().corrections_before_init, 1u);
  feed(fuser, truth, 0, 200);
  fuser.add_imu(sample_at(truth, sample_time(150)));
  EXPECT_EQ(fuser.stats().samples_out_of_order, 1u);
  EXPECT_FALSE(correct_scan(fuser, sample_time(250), identity, 0.01).pose_reset);  // newer than the IMU
  EXPECT_EQ(fuser.stats().anchors_while_imu_silent, 1u);  // kept for an IMU gap, not applied
  EXPECT_FALSE(correct_scan(fuser, sample_time(50), identity, 0.01).pose_reset);   // before the history
  EXPECT_EQ(fuser.stats().corrections_outside_history, 1u);
  const CorrectionResult result = correct_scan(fuser, sample_time(180), identity, 0.01);
  EXPECT_TRUE(result.pose_reset);
  EXPECT_TRUE(std::isfinite(result.rewritten_after_s));
}

TEST(ImuFuser, BuffersStayBounded) {
  Truth truth;
  ImuFuserParams params;
  params.history_capacity = 64;
  params.trajectory_capacity = 32;
  ImuFuser fuser(params);
  feed(fuser, truth, 0, 2000);
  EXPECT_EQ(fuser.trajectory().size(), 32u);
  EXPECT_DOUBLE_EQ(fuser.trajectory().t_end_s(), sample_time(2000));
  // A correction older than the 64-sample history cannot be placed.
  EXPECT_FALSE(correct_scan(fuser, sample_time(1900), Eigen::Isometry3d::Identity(), 0.01).pose_reset);
  EXPECT_TRUE(correct_scan(fuser, sample_time(1990), Eigen::Isometry3d::Identity(), 0.01).pose_reset);
}

}  // namespace
}  // namespace tumble

namespace tumble {
namespace {

TEST(ImuFuser, StartsAgainFromTheRegisteredPosesAfterAnImuGap) {
  Truth truth;
  ImuFuser fuser(ImuFuserParams{});
  feed(fuser, truth, 0, 200);
  ASSERT_TRUE(fuser.initialized());
  // The IMU falls silent; the registration, predicting from its own poses,
  // reports two: 1 m/s along x, turning 1 rad/s about z.
  Eigen::Isometry3d a = Eigen::Isometry3d::Identity();
  a.translation() = Eigen::Vector3d(1.0, 0.0, 0.0);
  Eigen::Isometry3d b = a;
  b.translation() = Eigen::Vector3d(1.1, 0.0, 0.0);
  b.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  correct_scan(fuser, sample_time(220), a, 0.01);
  correct_scan(fuser, sample_time(230), b, 0.01);
  EXPECT_EQ(fuser.stats().anchors_while_imu_silent, 2u);
  fuser.add_imu(sample_at(truth, sample_time(240)));  // back after 0.4 s
  EXPECT_EQ(fuser.stats().reanchors, 1u);
  const TrajectorySample& s = fuser.trajectory().back();
  EXPECT_EQ(fuser.trajectory().size(), 1u);  // nothing integrated across the gap
  EXPECT_NEAR(s.p_w.x(), 1.2, 1e-9);         // carried on at the registrations' velocity
  EXPECT_NEAR(s.v_w.x(), 1.0, 1e-9);
  EXPECT_NEAR(Eigen::AngleAxisd(s.q_wl).angle(), 0.2, 1e-9);  // and body rate
  // Those registrations were not de-skewed: their velocity is a guess.
  const double bridged = ImuFuserParams{}.bridged_velocity_sigma_m_s;
  EXPECT_GE(fuser.velocity_variance().minCoeff(), bridged * bridged);
}

// Bridges an IMU gap with two registered poses at rest (samples 220 and 230)
// and brings the IMU back at sample 240.
void bridge_a_gap_at_rest(ImuFuser& fuser, const Truth& truth) {
  feed(fuser, truth, 0, 200);
  const Eigen::Isometry3d at_rest = Eigen::Isometry3d::Identity();
  correct_scan(fuser, sample_time(220), at_rest, 0.01);
  correct_scan(fuser, sample_time(230), at_rest, 0.01);
  fuser.add_imu(sample_at(truth, sample_time(240)));
}

// Feeds samples n_from..n_to with a registration at the truth every 10 samples.
void feed_registered(ImuFuser& fuser, const Truth& truth, int n_from, int n_to) {
  for (int n = n_from; n + 9 <= n_to; n += 10) {
    feed(fuser, truth, n, n + 9);
    correct_scan(fuser, sample_time(n), at_pose(truth, sample_time(n)), 0.01);
  }
}

TEST(ImuFuser, AfterAnImuGapTheVelocityIsUnconfirmedUntilARestFindsItStill) {
  Truth truth;
  ImuFuser fuser(ImuFuserParams{});
  EXPECT_TRUE(fuser.velocity_confirmed());
  bridge_a_gap_at_rest(fuser, truth);
  ASSERT_EQ(fuser.stats().reanchors, 1u);
  EXPECT_FALSE(fuser.velocity_confirmed());  // the registrations' guess
  feed_registered(fuser, truth, 241, 280);   // still for 0.4 s: under fuser.rest_static_s
  EXPECT_FALSE(fuser.velocity_confirmed());
  feed_registered(fuser, truth, 281, 330);  // a still window, and the registrations after it
  EXPECT_TRUE(fuser.velocity_confirmed());
  EXPECT_EQ(fuser.stats().runaways_at_rest, 0u);
}

// The IMU still from sample 241 on while the registrations move the robot
// at 1 m/s along x (a scene that repeats, fitted a little further each scan);
// with or without an IMU gap before.
ImuFuser registrations_slide_while_the_imu_is_still(bool gap_first) {
  Truth still;
  Truth sliding;
  sliding.p_w = [](double t) { return Eigen::Vector3d(std::max(t - sample_time(241), 0.0), 0.0, 0.0); };
  ImuFuser fuser(ImuFuserParams{});
  if (gap_first) {
    bridge_a_gap_at_rest(fuser, still);
  } else {
    feed(fuser, still, 0, 240);
  }
  for (int n = 250; n <= 450; n += 10) {
    feed(fuser, still, n - 9, n);
    correct_scan(fuser, sample_time(n - 5), at_pose(sliding, sample_time(n - 5)), 0.01);
  }
  return fuser;
}

TEST(ImuFuser, AfterAnImuGapARestThatFindsTheRobotMovingIsARunaway) {
  const ImuFuser fuser = registrations_slide_while_the_imu_is_still(true);
  EXPECT_GT(fuser.trajectory().back().v_w.x(), 0.5);  // the registrations' velocity
  EXPECT_GE(fuser.stats().runaways_at_rest, 1u);
  EXPECT_FALSE(fuser.velocity_confirmed());
}

TEST(ImuFuser, WithoutAGapAStillImuIsNoRest) {
  // A cruise at constant velocity looks still to the IMU: its velocity,
  // measured all along, is not judged by it.
  const ImuFuser fuser = registrations_slide_while_the_imu_is_still(false);
  EXPECT_GT(fuser.trajectory().back().v_w.x(), 0.5);
  EXPECT_EQ(fuser.stats().runaways_at_rest, 0u);
  EXPECT_TRUE(fuser.velocity_confirmed());
}

TEST(ImuFuser, ScansAlongAnAxisTheyPinWeaklyMeasureLittleOfTheVelocityThere) {
  // As AScanThatHeldATranslationDoesNotMeasureTheVelocityAlongIt, but the
  // scan's own covariance is wide along x: its position there is the prior's.
  const Truth truth = at_rest_with_a_second_of_accel_bias();
  ImuFuser fuser(device_attitude_params());
  const double t_previous = kMotionStart + 1.203;
  const double t_scan = t_previous + 0.1;
  const Eigen::Isometry3d at_rest = pose_of(Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero());
  const Eigen::Vector3d wide_along_x(1.0, 1e-6, 1e-6);  // (1 m)² along x
  feed(fuser, truth, 0, 255);
  fuser.correct_with_registered_pose({.t_start_s = t_previous,
                                      .t_end_s = t_previous + kScanS,
                                      .T_wl = at_rest,
                                      .position_sigma_m = 1e-3,
                                      .position_var_w_m2 = wide_along_x});
  feed(fuser, truth, 256, 265);
  const Eigen::Vector3d v_before = fuser.trajectory().back().v_w;
  ASSERT_GT(v_before.x(), 0.4);
  ASSERT_GT(v_before.y(), 0.4);
  fuser.correct_with_registered_pose({.t_start_s = t_scan,
                                      .t_end_s = t_scan + kScanS,
                                      .T_wl = at_rest,
                                      .position_sigma_m = 1e-3,
                                      .position_var_w_m2 = wide_along_x});
  const Eigen::Vector3d v_after = fuser.trajectory().back().v_w;
  EXPECT_NEAR(v_after.y(), 0.0, 1e-2);         // pinned: corrected
  EXPECT_GT(v_after.x(), 0.9 * v_before.x());  // wide: hardly moved
}

TEST(ImuFuser, AJumpReanchorsThePoseButIsNoVelocityMeasurement) {
  Truth truth;
  ImuFuser fuser(device_attitude_params());
  feed(fuser, truth, 0, 250);
  const Eigen::Isometry3d at_rest = pose_of(Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero());
  correct_scan(fuser, sample_time(230), at_rest, 0.01);
  const Eigen::Isometry3d far = pose_of(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.5, 0.0, 0.0));
  const CorrectionResult result = fuser.correct_with_registered_pose({.t_start_s = sample_time(240),
                                                                      .t_end_s = sample_time(240) + kScanS,
                                                                      .T_wl = far,
                                                                      .position_sigma_m = 0.01,
                                                                      .jumped = true});
  EXPECT_TRUE(result.pose_reset);
  EXPECT_FALSE(result.velocity_updated);
  EXPECT_EQ(fuser.stats().jumps, 1u);
  EXPECT_NEAR(fuser.trajectory().back().p_w.x(), 0.5, 1e-6);  // the pose is the registration's
  EXPECT_NEAR(fuser.trajectory().back().v_w.x(), 0.0, 1e-6);  // the velocity is not 5 m/s
  // As uncertain as the jump says: 0.5 m over the 0.1 s interval.
  EXPECT_GE(fuser.velocity_variance().minCoeff(), 25.0 - 1e-6);
}

TEST(ImuFuser, AfterALossItHoldsThePositionUntilTheRobotRestsThenStartsFromZeroVelocity) {
  // Moving at 1 m/s along x and turning at 0.3 rad/s with the velocity
  // measured, then lost. (The turn is what tells the IMU it is not still:
  // a constant velocity alone would look like rest.)
  constexpr double kYawRate = 0.3;
  Truth truth;
  truth.p_w = [](double t) { return Eigen::Vector3d(std::max(t - kMotionStart, 0.0), 0.0, 0.0); };
  truth.v_w = [](double t) { return Eigen::Vector3d(t > kMotionStart ? 1.0 : 0.0, 0.0, 0.0); };
  truth.q_wi = [](double t) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(kYawRate * std::max(t - kMotionStart, 0.0), Eigen::Vector3d::UnitZ()));
  };
  truth.omega_i = [](double t) { return Eigen::Vector3d(0.0, 0.0, t > kMotionStart ? kYawRate : 0.0); };
  ImuFuserParams params = device_attitude_params();
  params.attitude_from_device = false;
  ImuFuser fuser(params);
  feed(fuser, truth, 0, 200);
  ASSERT_TRUE(fuser.initialized());
  for (int n = 210; n <= 300; n += 10) {
    feed(fuser, truth, n - 9, n);
    correct_scan(fuser, sample_time(n - 5), at_pose(truth, sample_time(n - 5)), 0.01);
  }
  ASSERT_GT(fuser.trajectory().back().v_w.x(), 0.8);  // the velocity it had, to be dropped
  fuser.restart_at_rest();
  EXPECT_TRUE(fuser.awaiting_rest());
  const double held_x = fuser.trajectory().back().p_w.x();
  feed(fuser, truth, 301, 400);  // still moving: the position is held, the velocity unknown
  EXPECT_TRUE(fuser.awaiting_rest());
  EXPECT_EQ(fuser.trajectory().back().p_w.x(), held_x);
  EXPECT_EQ(fuser.trajectory().back().v_w.x(), 0.0);
  EXPECT_GE(fuser.velocity_variance().minCoeff(), 1.0);
  const CorrectionResult ignored = correct_scan(fuser, sample_time(395), at_pose(truth, sample_time(395)), 0.01);
  EXPECT_FALSE(ignored.pose_reset);
  EXPECT_EQ(fuser.stats().corrections_awaiting_rest, 1u);
  // The robot stops: a static window later the fuser starts again from rest.
  const Eigen::Quaterniond q_stop = truth.q_wi(sample_time(400));
  Truth stopped;
  stopped.p_w = [&](double) { return truth.p_w(sample_time(400)); };
  stopped.q_wi = [&](double) { return q_stop; };
  feed(fuser, stopped, 401, 430);
  EXPECT_TRUE(fuser.awaiting_rest());  // not yet rest_duration_s
  feed(fuser, stopped, 431, 520);
  EXPECT_FALSE(fuser.awaiting_rest());
  EXPECT_EQ(fuser.stats().rests, 1u);
  EXPECT_NEAR(fuser.trajectory().back().v_w.x(), 0.0, 1e-6);
  // Known again: the start's variance plus the process noise since the rest (under 1 s), not the wait's 100.
  EXPECT_LT(fuser.velocity_variance().maxCoeff(), 0.02);
  EXPECT_TRUE(correct_scan(fuser, sample_time(515), at_pose(stopped, sample_time(515)), 0.01).pose_reset);
}

}  // namespace
}  // namespace tumble
