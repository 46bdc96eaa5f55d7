// A drive through the synthetic room for tests that run the whole odometry:
// static, then a smooth ramp to a constant velocity and yaw rate, with the
// IMU samples that motion gives and RS-16-like scans of the room.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/odometry.hpp"
#include "core/parallel_runner.hpp"
#include "test/core/synthetic_room.hpp"

namespace tumble::test {

constexpr double kGravity = 9.80665;

// Static until t_go, then a smooth ramp (smoothstep over ramp_s) to a constant
// velocity along a fixed world direction and a constant yaw rate: the lidar
// stays level, so its body z is the world z and ω is (0, 0, yaw rate).
struct YawAndDrive {
  Eigen::Vector3d velocity_w{1.0, 0.3, 0.0};
  double yaw_rate_rad_s = 1.5;
  double t_go_s = 0.5;
  double ramp_s = 0.5;

  double tau(double t) const { return std::clamp((t - t_go_s) / ramp_s, 0.0, 1.0); }
  double speed_fraction(double t) const {  // s(τ)
    const double x = tau(t);
    return x * x * (3 - 2 * x);
  }
  double integral(double t) const {  // ∫ s dt from t_go
    if (t <= t_go_s) return 0;
    const double x = tau(t);
    return ramp_s * (x * x * x - x * x * x * x / 2) + std::max(0.0, t - t_go_s - ramp_s);
  }
  double speed_fraction_rate(double t) const {  // ds/dt
    const double x = tau(t);
    return (t <= t_go_s || x >= 1) ? 0.0 : 6 * x * (1 - x) / ramp_s;
  }

  Eigen::Isometry3d pose(double t) const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw_rate_rad_s * integral(t), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = velocity_w * integral(t);
    return T;
  }
  ImuSample imu(double t) const {
    ImuSample s;
    s.t_s = t;
    const Eigen::Vector3d a_w = velocity_w * speed_fraction_rate(t);
    s.accel_m_s2 = pose(t).linear().transpose() * (a_w + Eigen::Vector3d(0, 0, kGravity));
    s.gyro_rad_s = Eigen::Vector3d(0, 0, yaw_rate_rad_s * speed_fraction(t));
    return s;
  }
};

// Feeds `odometry` duration_s of the drive: 100 Hz IMU samples and 10 Hz
// scans in time order (a scan when its last point has been fired).
inline void feed_room_drive(Odometry& odometry, const YawAndDrive& motion, double duration_s, const RingLidar& lidar,
                            const Room& room = make_room()) {
  const double imu_dt = 0.01;
  double next_scan_start = 0.0;
  std::uint64_t scan_index = 0;
  for (int k = 0; k * imu_dt <= duration_s; ++k) {
    const double t = k * imu_dt;
    odometry.add_imu(motion.imu(t));
    while (next_scan_start + lidar.revolution_s <= t) {
      Scan scan;
      scan.index = scan_index++;
      scan.points = scan_room(room, [&](double ts) { return motion.pose(ts); }, next_scan_start, lidar);
      odometry.add_scan(scan);
      next_scan_start += lidar.revolution_s;
    }
  }
}

// Every scan result of duration_s of the drive, the registration's loops on `runner`.
inline std::vector<ScanResult> register_room_drive(const YawAndDrive& motion, const OdometryParams& params,
                                                   double duration_s, const RingLidar& lidar,
                                                   ParallelRunner& runner = serial_runner()) {
  Odometry odometry(params, {}, runner);
  std::vector<ScanResult> results;
  odometry.set_scan_callback([&](const ScanResult& r) { results.push_back(r); });
  feed_room_drive(odometry, motion, duration_s, lidar);
  return results;
}

// Two runs gave the same results, to the last bit.
inline void expect_same_results(const std::vector<ScanResult>& expected, const std::vector<ScanResult>& actual) {
  ASSERT_GE(expected.size(), 5u);
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t s = 0; s < expected.size(); ++s) {
    SCOPED_TRACE(s);
    EXPECT_TRUE(expected[s].T_wl.matrix() == actual[s].T_wl.matrix());
    EXPECT_EQ(expected[s].iterations, actual[s].iterations);
    EXPECT_EQ(expected[s].inlier_ratio, actual[s].inlier_ratio);
    EXPECT_EQ(expected[s].residual_rms_m, actual[s].residual_rms_m);
    EXPECT_EQ(expected[s].map_points, actual[s].map_points);
    EXPECT_EQ(expected[s].map_insert.inserted, actual[s].map_insert.inserted);
  }
}

}  // namespace tumble::test
