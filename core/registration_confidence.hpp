// How far a registered pose may be from the truth, without ground truth
// (issue 19): the ICP's covariance, calibrated. s²·H⁻¹ treats every match as
// independent, but neighbouring matches share their map points and normals,
// so it is optimistic by a roughly constant factor; and below a few
// millimetres the map's own error dominates.
//
// Calibrated on bench2 (94 runs of `tumble-sim bench --realistic` and its 12
// people runs, GVTW + de-skew) against the true error of each scan's pose
// increment (with both poses' covariances; `tumble-eval integrity`). Since
// the attitude is the gyro's alone between scans (imu_fuser.hpp, 2), κ = 4
// and a 2 mm floor give a mean NEES (per degree of freedom) of 0.51 over the
// 9 051 increments of the runs under 0.5 cm/m and 1.18 over those under
// 2 cm/m (bench1: 0.59, 1.71). κ = 7 and 3 mm, chosen with Madgwick's
// accelerometer step, gave 0.24 and 0.64 there. The errors are heavy-tailed:
// the median NEES is 0.1.
// The largest eigenvalue follows the real error (README, Knowing when the
// pose is wrong).
#pragma once

#include <Eigen/Core>

#include "core/icp.hpp"

namespace tumble {

struct RegistrationConfidenceParams {
  double covariance_scale = 4.0;   // κ: the published covariance is κ²·(ICP covariance) ...
  double position_floor_m = 0.002; // ... plus this² on the position diagonal
};

// The covariance to publish with a registered pose, over (tx, ty, tz, rx, ry, rz)
// like IcpResult::covariance. Not finite when the ICP's is not.
Matrix6d published_covariance(const Matrix6d& icp_covariance, const RegistrationConfidenceParams& params = {});

// The square root of the largest eigenvalue of the position block, m: the
// expected error along the least constrained direction (infinity when the
// covariance is not finite).
double expected_position_error_m(const Matrix6d& covariance);

}  // namespace tumble
