// How far a registered pose may be from the truth, without ground truth:
// the ICP's covariance, calibrated. s²·H⁻¹ treats every match as
// independent, but neighbouring matches share their map points and normals,
// so it is optimistic by a roughly constant factor (κ); and below a few
// millimetres the map's own error dominates (the floor). κ is chosen so that
// the mean NEES per degree of freedom of each scan's pose increment is near 1
// on the simulated benches; the errors are heavy-tailed, so the median is
// far below 1. The largest eigenvalue follows the real error.
//
// Where a scan hardly pins a direction (a lane, a corridor), what little
// information s²·H⁻¹ sees there is largely the normals' own noise, and the
// error it claims is too small. Taking the noise's share from every
// direction (without_normal_noise) widens only such directions.
// The values and the figures that chose them:
// docs/decisions/covariance-calibration.md.
#pragma once

#include <Eigen/Core>

#include "core/icp.hpp"

namespace tumble {

struct RegistrationConfidenceParams {
  double covariance_scale = 3.2;   // κ: the published covariance is κ²·(ICP covariance) ...
  double position_floor_m = 0.002; // ... plus this² on the position diagonal
  // without_normal_noise's share: what a direction no surface constrains
  // still gets of the weights (a corridor's axis gets about this much).
  double normal_noise_share = 0.0015;
};

// The covariance to publish with a registered pose, over (tx, ty, tz, rx, ry, rz)
// like IcpResult::covariance. Not finite when the ICP's is not.
Matrix6d published_covariance(const Matrix6d& icp_covariance, const RegistrationConfidenceParams& params = {});

// The ICP covariance without the information the normals' own noise gives
// every direction: `noise_share` (of the weights' sum, like
// Degeneracy::min_eigenvalue) is taken from each eigenvalue of the balanced
// normal matrix, down to a hundredth of it (σ at most 10× wider). Needs the
// degeneracy report of the same ICP result (its s²/W and length scale);
// unchanged without one.
Matrix6d without_normal_noise(const Matrix6d& icp_covariance, const Degeneracy& degeneracy, double noise_share);

// The square root of the largest eigenvalue of the position block, m: the
// expected error along the least constrained direction (infinity when the
// covariance is not finite).
double expected_position_error_m(const Matrix6d& covariance);

// The same for the rotation block, rad: the expected attitude error about the
// least constrained axis.
double expected_rotation_error_rad(const Matrix6d& covariance);

}  // namespace tumble
