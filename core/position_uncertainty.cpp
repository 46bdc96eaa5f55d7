#include "core/position_uncertainty.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tumble {

void check_position_uncertainty_params(const PositionUncertaintyParams& params) {
  if (!(params.prediction_sigma_m >= 0) || !std::isfinite(params.prediction_sigma_m))
    throw std::invalid_argument("PositionUncertaintyParams: prediction_sigma_m must be finite and >= 0, got " +
                                std::to_string(params.prediction_sigma_m));
}

PositionUncertainty::PositionUncertainty(const PositionUncertaintyParams& params) : params_(params) {
  check_position_uncertainty_params(params);
}

Eigen::Matrix3d PositionUncertainty::predicted() const {
  return covariance_ + params_.prediction_sigma_m * params_.prediction_sigma_m * Eigen::Matrix3d::Identity();
}

Eigen::Matrix3d PositionUncertainty::prior_information(double covariance_scale) const {
  if (!enabled()) return Eigen::Matrix3d::Zero();
  return covariance_scale * covariance_scale * predicted().inverse();
}

Matrix6d PositionUncertainty::fuse(const Matrix6d& scan_covariance) {
  // The prediction as a measurement of the position (Kalman form: no
  // inverse of the scan's covariance, which is huge along an unpinned direction).
  const Eigen::Matrix3d innovation = scan_covariance.topLeftCorner<3, 3>() + predicted();
  const Eigen::Matrix<double, 6, 3> gain = scan_covariance.leftCols<3>() * innovation.inverse();
  Matrix6d fused = scan_covariance - gain * scan_covariance.topRows<3>();
  fused = 0.5 * (fused + fused.transpose());
  covariance_ = fused.topLeftCorner<3, 3>();
  return fused;
}

void PositionUncertainty::take(const Matrix6d& scan_covariance) {
  if (!scan_covariance.topLeftCorner<3, 3>().allFinite()) {
    predict_only();
    return;
  }
  covariance_ = scan_covariance.topLeftCorner<3, 3>();
}

void PositionUncertainty::predict_only() { covariance_ = predicted(); }

void PositionUncertainty::reset() { covariance_.setZero(); }

}  // namespace tumble
