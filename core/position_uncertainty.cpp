#include "core/position_uncertainty.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tumble {

void check_position_uncertainty_params(const PositionUncertaintyParams& params) {
  if (!(params.prediction_sigma_m >= 0) || !std::isfinite(params.prediction_sigma_m))
    throw std::invalid_argument("PositionUncertaintyParams: prediction_sigma_m must be finite and >= 0, got " +
                                std::to_string(params.prediction_sigma_m));
  if (!(params.scan_interval_s > 0) || !std::isfinite(params.scan_interval_s))
    throw std::invalid_argument("PositionUncertaintyParams: scan_interval_s must be finite and > 0, got " +
                                std::to_string(params.scan_interval_s));
  if (!(params.jump_sigmas >= 0) || !std::isfinite(params.jump_sigmas))
    throw std::invalid_argument("PositionUncertaintyParams: jump_sigmas must be finite and >= 0, got " +
                                std::to_string(params.jump_sigmas));
}

PositionUncertainty::PositionUncertainty(const PositionUncertaintyParams& params) : params_(params) {
  check_position_uncertainty_params(params);
}

Eigen::Matrix3d PositionUncertainty::predicted(double t_s, const Eigen::Vector3d& velocity_var_w_m2_s2) const {
  // At least one interval (the first scan, scans closer than the period);
  // a longer gap's velocity error grows the position error linearly, its
  // variance quadratically.
  const double intervals =
      std::isfinite(updated_at_s_) ? std::max((t_s - updated_at_s_) / params_.scan_interval_s, 1.0) : 1.0;
  const double sigma_m = params_.prediction_sigma_m * intervals;
  const double elapsed_s = intervals * params_.scan_interval_s;
  const Eigen::Vector3d velocity_var = velocity_var_w_m2_s2.allFinite() ? velocity_var_w_m2_s2 : Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = covariance_ + sigma_m * sigma_m * Eigen::Matrix3d::Identity();
  covariance.diagonal() += elapsed_s * elapsed_s * velocity_var;
  return covariance;
}

Eigen::Matrix3d PositionUncertainty::prior_information(double t_s, double covariance_scale,
                                                       const Eigen::Vector3d& velocity_var_w_m2_s2) const {
  if (!enabled()) return Eigen::Matrix3d::Zero();
  return covariance_scale * covariance_scale * predicted(t_s, velocity_var_w_m2_s2).inverse();
}

bool PositionUncertainty::jumped(double t_s, const Eigen::Vector3d& correction_w_m,
                                 const Eigen::Matrix3d& scan_position_covariance) const {
  if (!enabled() || params_.jump_sigmas <= 0 || !scan_position_covariance.allFinite()) return false;
  const Eigen::Matrix3d both = predicted(t_s) + scan_position_covariance;
  const double limit = params_.jump_sigmas * params_.jump_sigmas;
  return correction_w_m.dot(both.ldlt().solve(correction_w_m)) > limit;
}

Matrix6d PositionUncertainty::fuse(double t_s, const Matrix6d& scan_covariance,
                                   const Eigen::Vector3d& velocity_var_w_m2_s2) {
  if (!scan_covariance.allFinite()) {
    predict_only(t_s, velocity_var_w_m2_s2);
    return scan_covariance;
  }
  // The prediction as a measurement of the position, in the Kalman form
  // (no inverse of the scan's covariance, which is huge along an unpinned
  // direction), arranged so that nothing cancels: C − C S⁻¹ C over the
  // translation is C S⁻¹ P, which stays P where C is huge.
  const Eigen::Matrix3d prediction = predicted(t_s, velocity_var_w_m2_s2);
  const Eigen::Matrix3d s_inverse = (scan_covariance.topLeftCorner<3, 3>() + prediction).inverse();
  const Eigen::Matrix3d c_tt = scan_covariance.topLeftCorner<3, 3>();
  const Eigen::Matrix3d c_rt = scan_covariance.bottomLeftCorner<3, 3>();
  Matrix6d fused;
  fused.topLeftCorner<3, 3>() = c_tt * s_inverse * prediction;
  fused.bottomLeftCorner<3, 3>() = c_rt * s_inverse * prediction;
  fused.topRightCorner<3, 3>() = fused.bottomLeftCorner<3, 3>().transpose();
  fused.bottomRightCorner<3, 3>() = scan_covariance.bottomRightCorner<3, 3>() - c_rt * s_inverse * c_rt.transpose();
  fused = 0.5 * (fused + fused.transpose());
  covariance_ = fused.topLeftCorner<3, 3>();
  updated_at_s_ = t_s;
  return fused;
}

void PositionUncertainty::replace_with_scan(double t_s, const Matrix6d& scan_covariance,
                                            const Eigen::Vector3d& velocity_var_w_m2_s2) {
  if (!scan_covariance.topLeftCorner<3, 3>().allFinite()) {
    predict_only(t_s, velocity_var_w_m2_s2);
    return;
  }
  covariance_ = scan_covariance.topLeftCorner<3, 3>();
  updated_at_s_ = t_s;
}

void PositionUncertainty::predict_only(double t_s, const Eigen::Vector3d& velocity_var_w_m2_s2) {
  covariance_ = predicted(t_s, velocity_var_w_m2_s2);
  updated_at_s_ = t_s;
}

void PositionUncertainty::reset(double t_s) {
  covariance_.setZero();
  updated_at_s_ = t_s;
}

}  // namespace tumble
