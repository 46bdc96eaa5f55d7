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

TEST(RegistrationConfidence, ExpectedErrorIsAlongTheLeastConstrainedDirectionWhateverItsAxes) {
  // 1 mm across a corridor, 5 cm along it, the corridor at 30 degrees in W.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d sigmas_m(0.05, 0.001, 0.001);
  Matrix6d covariance = Matrix6d::Identity() * 1e-6;
  covariance.topLeftCorner<3, 3>() = R * sigmas_m.cwiseAbs2().asDiagonal() * R.transpose();
  EXPECT_NEAR(expected_position_error_m(covariance), 0.05, 1e-9);
  covariance(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(std::isinf(expected_position_error_m(covariance)));
}

}  // namespace
}  // namespace tumble
