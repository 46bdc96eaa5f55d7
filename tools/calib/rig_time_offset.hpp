// The lidar-IMU time offset: the shift of the IMU's clock (tumbled's
// imu.imu_time_offset_s, added to every IMU time) under which the gyro's
// rotations over the lidar's scan intervals agree best with the lidar's.
//  - coarse: cross-correlation of the rotation magnitudes |r_L| and |r_I|
//    over a grid of offsets (magnitudes do not depend on the unknown R_LI);
//  - fine: the hand-eye rotation's residual over a finer grid around it,
//    minimum by a parabola through the best grid point and its neighbours;
//    σ from the parabola's curvature and the residual variance.
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "core/types.hpp"
#include "tools/calib/rig_rotation.hpp"

namespace tumble::calib {

// The lidar's rotation between two registered scans (lidar frame at t0).
struct LidarRotation {
  double t0_s = 0.0;
  double t1_s = 0.0;
  Eigen::Vector3d rotation_rad = Eigen::Vector3d::Zero();
};

// The increments with the gyro integrated over each interval at that offset (no bias).
std::vector<RotationIncrement> rotation_increments(std::span<const LidarRotation> lidar,
                                                   std::span<const ImuSample> imu, double offset_s);

// Pearson correlation of |r_L| and |r_I| at that offset (0 when undefined).
double magnitude_correlation(std::span<const LidarRotation> lidar, std::span<const ImuSample> imu, double offset_s);

struct TimeOffsetEstimate {
  double offset_s = 0.0;
  double sigma_s = 0.0;    // fine search only
  double score = 0.0;      // coarse: the correlation; fine: the residual sum of squares (rad²)
  bool at_edge = false;    // the best grid point is at the end of the searched range
};

// Grid [centre - half_width, centre + half_width] at step_s.
TimeOffsetEstimate coarse_time_offset(std::span<const LidarRotation> lidar, std::span<const ImuSample> imu,
                                      double centre_s, double half_width_s, double step_s);
TimeOffsetEstimate fine_time_offset(std::span<const LidarRotation> lidar, std::span<const ImuSample> imu,
                                    double centre_s, double half_width_s, double step_s, bool reject_outliers = true);

}  // namespace tumble::calib
