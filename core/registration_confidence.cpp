#include "core/registration_confidence.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

namespace tumble {

Matrix6d published_covariance(const Matrix6d& icp_covariance, const RegistrationConfidenceParams& params) {
  Matrix6d out = params.covariance_scale * params.covariance_scale * icp_covariance;
  out.diagonal().head<3>().array() += params.position_floor_m * params.position_floor_m;
  return out;
}

Matrix6d without_normal_noise(const Matrix6d& icp_covariance, const Degeneracy& degeneracy, double noise_share) {
  const double s2_per_weight = degeneracy.residual_variance_per_weight;
  if (!(s2_per_weight > 0) || !(noise_share > 0) || !icp_covariance.allFinite()) return icp_covariance;
  Vector6d balance;
  balance << 1, 1, 1, degeneracy.length_scale_m, degeneracy.length_scale_m, degeneracy.length_scale_m;
  // s²·H⁻¹ of the balanced H: an eigenvalue μ = s²/λ, so λ's share of the weights is (s²/W)/μ.
  const Matrix6d balanced = balance.asDiagonal() * icp_covariance * balance.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Matrix6d> solver(balanced);
  const Vector6d mu = solver.eigenvalues();
  Vector6d widened;
  for (int e = 0; e < 6; ++e) {
    if (!(mu(e) > 0)) {
      widened(e) = mu(e);
      continue;
    }
    const double share = s2_per_weight / mu(e);
    widened(e) = s2_per_weight / std::max(share - noise_share, 0.01 * share);
  }
  const Matrix6d out = solver.eigenvectors() * widened.asDiagonal() * solver.eigenvectors().transpose();
  const Vector6d unbalance = balance.cwiseInverse();
  return unbalance.asDiagonal() * out * unbalance.asDiagonal();
}

namespace {

double sqrt_largest_eigenvalue(const Eigen::Matrix3d& block) {
  if (!block.allFinite()) return std::numeric_limits<double>::infinity();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(block, Eigen::EigenvaluesOnly);
  return std::sqrt(std::max(solver.eigenvalues().maxCoeff(), 0.0));
}

}  // namespace

double expected_position_error_m(const Matrix6d& covariance) {
  return sqrt_largest_eigenvalue(covariance.topLeftCorner<3, 3>());
}

double expected_rotation_error_rad(const Matrix6d& covariance) {
  return sqrt_largest_eigenvalue(covariance.bottomRightCorner<3, 3>());
}

}  // namespace tumble
