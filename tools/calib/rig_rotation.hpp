// The lidar-IMU rotation from rotation increments seen by both sensors
// (hand-eye rotation): over the interval between two registered scans the
// lidar turned by r_L (rotation vector, lidar frame) and the gyro integrated
// r_I (IMU frame). A rigid mount gives r_L = R_LI (r_I - b dt) with b the gyro
// bias, so R_LI is the rotation that best maps the r_I onto the r_L
// (Kabsch / Wahba by SVD), alternated with the bias in closed form, and
// increments whose residual is far beyond the typical one (a bad
// registration) are left out.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <vector>

namespace tumble::calib {

struct RotationIncrement {
  Eigen::Vector3d lidar_rad = Eigen::Vector3d::Zero();  // r_L
  Eigen::Vector3d gyro_rad = Eigen::Vector3d::Zero();   // r_I, integrated without bias correction
  double dt_s = 0.0;
};

struct HandEyeRotation {
  Eigen::Matrix3d R_li = Eigen::Matrix3d::Identity();
  Eigen::Vector3d gyro_bias_rad_s = Eigen::Vector3d::Zero();
  double rms_residual_rad = 0.0;  // per axis, over the increments used
  double sum_squared_residual_rad2 = 0.0;
  double sigma_deg = 0.0;         // 1 σ of the rotation, largest axis (from the residuals)
  std::size_t used = 0;
  std::vector<bool> inlier;       // per increment
};

// Needs at least 3 increments spanning 3 axes (else the result is Identity
// with used = 0). reject_outliers = false keeps every increment (a first,
// biased registration whose errors grow with the motion).
HandEyeRotation align_rotation_increments(std::span<const RotationIncrement> increments, bool reject_outliers = true);

// The smallest eigenvalue of Σ r r^T / n over the lidar increments (rad²): how
// well the motion turned about its least-turned axis.
double weakest_axis_excitation_rad2(std::span<const RotationIncrement> increments);

}  // namespace tumble::calib
