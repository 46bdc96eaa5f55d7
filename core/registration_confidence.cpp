#include "core/registration_confidence.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

namespace tumble {

Matrix6d published_covariance(const Matrix6d& icp_covariance, const RegistrationConfidenceParams& params) {
  Matrix6d out = params.covariance_scale * params.covariance_scale * icp_covariance;
  out.diagonal().head<3>().array() += params.position_floor_m * params.position_floor_m;
  return out;
}

double expected_position_error_m(const Matrix6d& covariance) {
  const Eigen::Matrix3d position = covariance.topLeftCorner<3, 3>();
  if (!position.allFinite()) return std::numeric_limits<double>::infinity();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(position, Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(solver.eigenvalues().maxCoeff(), 0.0));
}

}  // namespace tumble
