#include "core/registration_confidence.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace tumble {
namespace {

TEST(RegistrationConfidence, ScalesTheIcpCovarianceAndAddsThePositionFloor) {
  Matrix6d icp = Matrix6d::Zero();
  icp.diagonal() << 1e-6, 4e-6, 9e-6, 1e-8, 1e-8, 1e-8;
  const RegistrationConfidenceParams params{.covariance_scale = 7.0, .position_floor_m = 0.003};
  const Matrix6d out = published_covariance(icp, params);
  EXPECT_NEAR(out(0, 0), 49 * 1e-6 + 9e-6, 1e-15);
  EXPECT_NEAR(out(2, 2), 49 * 9e-6 + 9e-6, 1e-15);
  EXPECT_NEAR(out(3, 3), 49 * 1e-8, 1e-18);  // no floor on rotation
  EXPECT_EQ(out(0, 1), 0.0);
}

// s²·H⁻¹ for a balanced normal matrix with these eigenvalues (shares of the
// weights' sum W) along the rotated axes, rotation balanced by length_m, and
// the degeneracy report that comes with it.
struct IcpOutcome {
  Matrix6d covariance;
  Degeneracy degeneracy;
};
IcpOutcome icp_outcome(const Vector6d& information_share, double s2_over_w, double length_m, const Matrix6d& axes) {
  const Vector6d mu = s2_over_w * information_share.cwiseInverse();
  Vector6d unbalance;
  unbalance << 1, 1, 1, 1 / length_m, 1 / length_m, 1 / length_m;
  IcpOutcome out;
  out.covariance = unbalance.asDiagonal() * (axes * mu.asDiagonal() * axes.transpose()) * unbalance.asDiagonal();
  out.degeneracy.min_eigenvalue = information_share.minCoeff();
  out.degeneracy.length_scale_m = length_m;
  out.degeneracy.residual_variance_per_weight = s2_over_w;
  return out;
}

TEST(RegistrationConfidence, TheNormalsNoiseIsTakenFromEveryDirectionsInformation) {
  // A lane along a direction 30 degrees off x: 0.002 of W there, the rest pinned.
  Matrix6d axes = Matrix6d::Identity();
  axes.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Vector6d share;
  share << 0.002, 0.2, 0.3, 0.05, 0.1, 0.1;
  const IcpOutcome icp = icp_outcome(share, 1e-6, 4.0, axes);
  const Matrix6d out = without_normal_noise(icp.covariance, icp.degeneracy, 0.0015);
  const Eigen::Vector3d lane = axes.col(0).head<3>();
  // The lane keeps 0.0005 of W: its variance grows 4 times.
  EXPECT_NEAR(lane.dot(out.topLeftCorner<3, 3>() * lane), 4.0 * 1e-6 / 0.002, 1e-9);
  EXPECT_NEAR(expected_position_error_m(out), 2.0 * expected_position_error_m(icp.covariance), 1e-9);
  // A pinned direction hardly changes: 0.2 -> 0.1985 of W.
  const Eigen::Vector3d across = axes.col(1).head<3>();
  EXPECT_NEAR(across.dot(out.topLeftCorner<3, 3>() * across), 1e-6 / 0.1985, 1e-12);
  // Rotation in radians: 0.05 of W at a length of 4 m -> 0.0485.
  EXPECT_NEAR(out(3, 3), 1e-6 / 0.0485 / 16.0, 1e-12);
  EXPECT_TRUE(out.isApprox(out.transpose()));

  // Information below the noise's: the variance grows 100 times, no more.
  const Matrix6d corridor = without_normal_noise(icp.covariance, icp.degeneracy, 0.01);
  EXPECT_NEAR(lane.dot(corridor.topLeftCorner<3, 3>() * lane), 100.0 * 1e-6 / 0.002, 1e-7);

  // A direction ICP could not solve at all (its eigenvalue below the
  // pseudo-inverse's cutoff, the covariance huge there) does not change what
  // the others keep: the share comes from s²/W, not from the weakest direction.
  share(0) = 1e-9;
  const IcpOutcome singular = icp_outcome(share, 1e-6, 4.0, axes);
  const Matrix6d from_singular = without_normal_noise(singular.covariance, singular.degeneracy, 0.0015);
  EXPECT_NEAR(across.dot(from_singular.topLeftCorner<3, 3>() * across), 1e-6 / 0.1985, 1e-9);
  EXPECT_NEAR(lane.dot(from_singular.topLeftCorner<3, 3>() * lane), 100.0 * 1e-6 / 1e-9, 1.0);

  // Nothing to take, or no s²/W to take it with: unchanged.
  EXPECT_EQ(without_normal_noise(icp.covariance, icp.degeneracy, 0.0), icp.covariance);
  Degeneracy unreported = icp.degeneracy;
  unreported.residual_variance_per_weight = 0.0;
  EXPECT_EQ(without_normal_noise(icp.covariance, unreported, 0.0015), icp.covariance);
}

TEST(RegistrationConfidence, ExpectedErrorIsAlongTheLeastConstrainedDirectionWhateverItsAxes) {
  // 1 mm across a corridor, 5 cm along it, the corridor at 30 degrees in W.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d sigmas_m(0.05, 0.001, 0.001);
  Matrix6d covariance = Matrix6d::Identity() * 1e-6;
  covariance.topLeftCorner<3, 3>() = R * sigmas_m.cwiseAbs2().asDiagonal() * R.transpose();
  EXPECT_NEAR(expected_position_error_m(covariance), 0.05, 1e-9);
  // The attitude is 1 mrad sure about every axis but one tilted axis, 3 mrad:
  // its expected error is that one's, whatever the position's.
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  covariance.bottomRightCorner<3, 3>() = tilt * Eigen::Vector3d(1e-6, 9e-6, 1e-6).asDiagonal() * tilt.transpose();
  EXPECT_NEAR(expected_rotation_error_rad(covariance), 0.003, 1e-9);
  covariance(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(std::isinf(expected_position_error_m(covariance)));
  EXPECT_NEAR(expected_rotation_error_rad(covariance), 0.003, 1e-9);  // the position block is not read
  covariance(4, 4) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isinf(expected_rotation_error_rad(covariance)));
}

}  // namespace
}  // namespace tumble
