// The gyro of a rig recording as a rotation source: the IMU's rotation over
// any time interval, with the IMU's clock shifted by a candidate lidar-IMU
// time offset and a constant bias taken out. Sample j measures the rate at
// samples[j].t_s + offset_s (tumbled's imu.imu_time_offset_s convention);
// between samples the rate is linear, beyond the ends it is held.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <span>

#include "core/types.hpp"

namespace tumble::calib {

struct GyroTiming {
  double offset_s = 0.0;                                     // added to every sample time
  Eigen::Vector3d bias_rad_s = Eigen::Vector3d::Zero();      // subtracted from every rate
};

// The rate (IMU frame, bias removed) at corrected time t_s.
Eigen::Vector3d gyro_rate_at(std::span<const ImuSample> samples, const GyroTiming& timing, double t_s);

// R_I(t0)ᵀ R_I(t1): the IMU frame at t1 in the IMU frame at t0 (t1 >= t0),
// integrated segment by segment between samples (midpoint rate).
Eigen::Quaterniond gyro_rotation(std::span<const ImuSample> samples, const GyroTiming& timing, double t0_s,
                                 double t1_s);

}  // namespace tumble::calib
