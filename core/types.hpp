// Plain data shared by drivers, core and tools. Times are seconds on the one
// host clock every source maps its sensor clock to (see drivers/).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

namespace tumble {

// Standard gravity (the MTi reports its ranges in g, the fuser and the tools
// model |g| with it).
inline constexpr double kStandardGravity_m_s2 = 9.80665;

// One lidar return, in the lidar frame at its own firing time.
struct LidarPoint {
  double t_s = 0.0;
  float x_m = 0.0f;
  float y_m = 0.0f;
  float z_m = 0.0f;
  float intensity = 0.0f;
  float azimuth_deg = 0.0f;
  std::uint8_t laser = 0;
  std::uint8_t return_index = 0;  // 0 = single/first return, 1 = second return (dual mode)
};

// One revolution of the lidar, points in firing order. points.front().t_s is the
// scan's time origin.
struct Scan {
  std::uint64_t index = 0;
  std::uint32_t missing_packets = 0;  // packets lost inside this revolution
  std::vector<LidarPoint> points;
};

// One IMU measurement in the IMU frame.
struct ImuSample {
  double t_s = 0.0;
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  // Clip bits from the device: the value on a saturated axis is not the truth.
  std::array<bool, 3> accel_saturated{};
  std::array<bool, 3> gyro_saturated{};
  // The device's own attitude estimate, when it sends one.
  bool has_orientation = false;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

}  // namespace tumble
