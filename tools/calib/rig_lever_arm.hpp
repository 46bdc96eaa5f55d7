// The lever arm t (the IMU's origin in the lidar frame) from the
// accelerations both sensors see. The IMU's specific force, turned into the
// lidar frame, is that of the lidar's origin plus the rigid-body terms of
// the arm:  R f_I = R_WLᵀ (a_L − g) + α × t + ω × (ω × t).
// The lidar's acceleration is taken over windows of registered scans
// a < b < c as the change of its mean velocity,
//   (p_c − p_b)/(c − b) − (p_b − p_a)/(b − a) = ∫ K(s) a_L(s) ds
// (K the hat of height 1 on [a, c], peak at b: exact for any motion), and
// the same integral of the IMU side is summed over the IMU samples, with
// R_WL(s) carried from the registered pose at b by the gyro. Unknowns,
// linear: t, the accelerometer bias and gravity in the map frame.
// t is observable only where the rotation's rate and acceleration excite
// it; its σ (from the residuals) says so.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <span>

#include "core/types.hpp"
#include "tools/calib/rig_registration.hpp"

namespace tumble::calib {

struct LeverArmEstimate {
  bool solved = false;  // false: too few windows, or the system is singular
  Eigen::Vector3d t_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d sigma_m = Eigen::Vector3d::Zero();       // 1 σ per lidar axis
  Eigen::Vector3d accel_bias_m_s2 = Eigen::Vector3d::Zero();  // IMU frame
  double gravity_m_s2 = 0.0;                               // |g| as fitted (a check: ~9.81)
  double rms_residual_m_s = 0.0;
  std::size_t windows = 0;
};

// windows: scans b−half_span, b, b+half_span, all registered and evenly spaced.
LeverArmEstimate estimate_lever_arm(std::span<const ScanPose> poses, std::span<const ImuSample> imu,
                                    const GyroModel& gyro, std::size_t half_span = 3);

}  // namespace tumble::calib
