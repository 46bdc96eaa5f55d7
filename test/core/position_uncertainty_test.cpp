#include "core/position_uncertainty.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace tumble {
namespace {

constexpr double kSigma = 0.02;
constexpr double kVar = kSigma * kSigma;

PositionUncertainty uncertainty() {
  return PositionUncertainty(PositionUncertaintyParams{.prediction_sigma_m = kSigma, .scan_interval_s = 0.1});
}

// A scan that pins y and z to 1 mm and says `along_x_m` along x.
Matrix6d scan_covariance(double along_x_m) {
  Matrix6d c = Matrix6d::Identity() * 1e-6;
  c(0, 0) = along_x_m * along_x_m;
  return c;
}

TEST(PositionUncertainty, GrowsByThePredictionEachScanThatPinsNothingAndShrinksWhereAScanPins) {
  PositionUncertainty position = uncertainty();
  position.reset(0.0);
  EXPECT_TRUE(position.predicted(0.1).isApprox(Eigen::Matrix3d::Identity() * kVar));

  // Along x the scan says 1 m: the prediction decides there, the scan in y and z.
  const Matrix6d fused = position.fuse(0.1, scan_covariance(1.0));
  EXPECT_NEAR(fused(0, 0), 1.0 / (1.0 / kVar + 1.0), 1e-12);
  EXPECT_NEAR(fused(1, 1), 1.0 / (1.0 / kVar + 1e6), 1e-12);
  EXPECT_DOUBLE_EQ(fused(3, 3), 1e-6);  // the rotation is the scan's
  // The next scan's prediction adds an interval's error to what this one knew.
  EXPECT_NEAR(position.predicted(0.2)(0, 0), fused(0, 0) + kVar, 1e-12);

  // Scans that say nothing along x: the uncertainty there grows as a
  // random walk of the prediction's errors, whatever they claim.
  double t = 0.1;
  for (int i = 0; i < 8; ++i) position.fuse(t += 0.1, scan_covariance(1e9));
  EXPECT_NEAR(position.predicted(t + 0.1)(0, 0), 10 * kVar, 1e-3 * kVar);
  // One that pins x brings it back.
  position.fuse(t += 0.1, scan_covariance(0.001));
  EXPECT_LT(std::sqrt(position.predicted(t + 0.1)(0, 0)), 1.1 * kSigma);
}

TEST(PositionUncertainty, AGapGrowsThePredictionWithItsLengthAndAScanNotRegisteredAddsIt) {
  PositionUncertainty position = uncertainty();
  position.reset(1.0);
  // Half a second without a scan: a velocity error carries on, 5 intervals' σ.
  EXPECT_NEAR(position.predicted(1.5)(2, 2), 25 * kVar, 1e-12);
  position.predict_only(1.1);
  position.predict_only(1.2);
  EXPECT_NEAR(position.predicted(1.3)(2, 2), 3 * kVar, 1e-12);
  position.replace_with_scan(1.3, Matrix6d::Identity() * std::numeric_limits<double>::infinity());  // as not registered
  EXPECT_NEAR(position.predicted(1.4)(2, 2), 4 * kVar, 1e-12);
  position.replace_with_scan(1.4, scan_covariance(0.5));  // registered without the prior: the scan's own
  EXPECT_NEAR(position.predicted(1.5)(0, 0), 0.25 + kVar, 1e-12);
  position.reset(1.5);
  EXPECT_TRUE(position.predicted(1.6).isApprox(Eigen::Matrix3d::Identity() * kVar));
  EXPECT_DOUBLE_EQ(position.updated_at_s(), 1.5);
}

TEST(PositionUncertainty, AScanCovarianceThatIsNotFiniteIsNotFusedAndLeavesNoNaN) {
  PositionUncertainty position = uncertainty();
  position.reset(0.0);
  Matrix6d broken = scan_covariance(0.1);
  broken(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(position.fuse(0.1, broken)(0, 0)));  // returned as it is ...
  EXPECT_TRUE(position.predicted(0.2).allFinite());            // ... and not kept
  EXPECT_NEAR(position.predicted(0.2)(0, 0), 2 * kVar, 1e-12);
  EXPECT_TRUE(position.prior_information(0.2, 3.2).allFinite());
}

TEST(PositionUncertainty, ThePriorInformationIsInTheUnitsOfTheUncalibratedCovariance) {
  PositionUncertainty position = uncertainty();
  position.reset(0.0);
  // κ = 2: the ICP's own covariance is a quarter of the calibrated one, so
  // the prior weighs 4× in its units.
  EXPECT_TRUE(position.prior_information(0.1, 2.0).isApprox(Eigen::Matrix3d::Identity() * 4.0 / kVar));
  PositionUncertainty off(PositionUncertaintyParams{});
  EXPECT_FALSE(off.enabled());
  EXPECT_TRUE(off.prior_information(0.1, 3.2).isZero());
}

TEST(PositionUncertainty, ThePredictionIsNoBetterThanTheFusersVelocity) {
  PositionUncertainty position = uncertainty();
  position.reset(0.0);
  // 0.5 m/s of velocity uncertainty along y over one 0.1 s interval: 5 cm more there.
  const Eigen::Vector3d velocity_var(0.0, 0.25, 0.0);
  const Eigen::Matrix3d predicted = position.predicted(0.1, velocity_var);
  EXPECT_NEAR(predicted(0, 0), kVar, 1e-12);
  EXPECT_NEAR(predicted(1, 1), kVar + 0.0025, 1e-12);
  // Over two intervals, twice the distance.
  EXPECT_NEAR(position.predicted(0.2, velocity_var)(1, 1), 4 * kVar + 4 * 0.0025, 1e-12);
  EXPECT_LT(position.prior_information(0.1, 1.0, velocity_var)(1, 1), 0.2 / kVar);
  // A velocity variance that is not finite adds nothing rather than NaN.
  EXPECT_TRUE(position.predicted(0.1, Eigen::Vector3d::Constant(std::nan(""))).allFinite());
}

TEST(PositionUncertainty, AJumpIsACorrectionManySigmaOfBothThePredictionAndTheScan) {
  PositionUncertainty position(
      PositionUncertaintyParams{.prediction_sigma_m = kSigma, .scan_interval_s = 0.1, .jump_sigmas = 5.0});
  position.reset(0.0);
  const Eigen::Matrix3d scan = Eigen::Matrix3d::Identity() * 1e-6;
  EXPECT_FALSE(position.jumped(0.1, Eigen::Vector3d(0.09, 0.0, 0.0), scan));  // 4.5 σ
  EXPECT_TRUE(position.jumped(0.1, Eigen::Vector3d(0.11, 0.0, 0.0), scan));   // 5.5 σ
  // Where the scan itself is uncertain, the same correction is no jump.
  Eigen::Matrix3d weak_x = scan;
  weak_x(0, 0) = 0.05 * 0.05;
  EXPECT_FALSE(position.jumped(0.1, Eigen::Vector3d(0.11, 0.0, 0.0), weak_x));
  // Off: the paper's ICP has no prediction to jump from.
  EXPECT_FALSE(uncertainty().jumped(0.1, Eigen::Vector3d(1.0, 0.0, 0.0), scan));
  EXPECT_THROW(PositionUncertainty(PositionUncertaintyParams{.prediction_sigma_m = kSigma, .jump_sigmas = -1.0}),
               std::invalid_argument);
}

TEST(PositionUncertainty, RejectsANegativeOrNonFiniteSigmaOrInterval) {
  EXPECT_THROW(PositionUncertainty(PositionUncertaintyParams{.prediction_sigma_m = -0.01}), std::invalid_argument);
  EXPECT_THROW(PositionUncertainty(PositionUncertaintyParams{.prediction_sigma_m = std::nan("")}),
               std::invalid_argument);
  EXPECT_THROW(PositionUncertainty(PositionUncertaintyParams{.prediction_sigma_m = 0.02, .scan_interval_s = 0}),
               std::invalid_argument);
}

}  // namespace
}  // namespace tumble
