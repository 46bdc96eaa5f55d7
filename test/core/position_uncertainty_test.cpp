#include "core/position_uncertainty.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace tumble {
namespace {

constexpr double kSigma = 0.02;

// A scan that pins y and z to 1 mm and says `along_x_m` along x.
Matrix6d scan_covariance(double along_x_m) {
  Matrix6d c = Matrix6d::Identity() * 1e-6;
  c(0, 0) = along_x_m * along_x_m;
  return c;
}

TEST(PositionUncertainty, GrowsByThePredictionEachScanThatPinsNothingAndShrinksWhereAScanPins) {
  PositionUncertainty position(PositionUncertaintyParams{.prediction_sigma_m = kSigma});
  EXPECT_TRUE(position.predicted().isApprox(Eigen::Matrix3d::Identity() * kSigma * kSigma));

  // Along x the scan says 1 m: the prediction decides there, the scan in y and z.
  const Matrix6d fused = position.fuse(scan_covariance(1.0));
  EXPECT_NEAR(fused(0, 0), 1.0 / (1.0 / (kSigma * kSigma) + 1.0), 1e-9);
  EXPECT_NEAR(fused(1, 1), 1.0 / (1.0 / (kSigma * kSigma) + 1e6), 1e-12);
  EXPECT_DOUBLE_EQ(fused(3, 3), 1e-6);  // the rotation is the scan's
  // The next scan's prediction adds an interval's error to what this one knew.
  EXPECT_NEAR(position.predicted()(0, 0), fused(0, 0) + kSigma * kSigma, 1e-12);

  // Scans that say nothing along x: the uncertainty there grows about
  // linearly, as a random walk of the prediction's errors.
  for (int i = 0; i < 8; ++i) position.fuse(scan_covariance(1e3));
  EXPECT_GT(std::sqrt(position.predicted()(0, 0)), 2.9 * kSigma);
  // One that pins x brings it back.
  position.fuse(scan_covariance(0.001));
  EXPECT_LT(std::sqrt(position.predicted()(0, 0)), 1.1 * kSigma);
}

TEST(PositionUncertainty, AScanNotRegisteredAddsThePredictionAndANewMapStartsFromNothing) {
  PositionUncertainty position(PositionUncertaintyParams{.prediction_sigma_m = kSigma});
  position.predict_only();
  position.predict_only();
  EXPECT_NEAR(position.predicted()(2, 2), 3 * kSigma * kSigma, 1e-12);
  position.take(Matrix6d::Identity() * std::numeric_limits<double>::infinity());  // no finite covariance: as not registered
  EXPECT_NEAR(position.predicted()(2, 2), 4 * kSigma * kSigma, 1e-12);
  position.take(scan_covariance(0.5));  // registered without the prior: the scan's own
  EXPECT_NEAR(position.predicted()(0, 0), 0.25 + kSigma * kSigma, 1e-12);
  position.reset();
  EXPECT_TRUE(position.predicted().isApprox(Eigen::Matrix3d::Identity() * kSigma * kSigma));
}

TEST(PositionUncertainty, ThePriorInformationIsInTheUnitsOfTheUncalibratedCovariance) {
  PositionUncertainty position(PositionUncertaintyParams{.prediction_sigma_m = kSigma});
  // κ = 2: the ICP's own covariance is a quarter of the calibrated one, so
  // the prior weighs 4× in its units.
  EXPECT_TRUE(position.prior_information(2.0).isApprox(Eigen::Matrix3d::Identity() * 4.0 / (kSigma * kSigma)));
  PositionUncertainty off(PositionUncertaintyParams{});
  EXPECT_FALSE(off.enabled());
  EXPECT_TRUE(off.prior_information(3.2).isZero());
}

TEST(PositionUncertainty, RejectsANegativeOrNonFiniteSigma) {
  EXPECT_THROW(PositionUncertainty(PositionUncertaintyParams{.prediction_sigma_m = -0.01}), std::invalid_argument);
  EXPECT_THROW(PositionUncertainty(PositionUncertaintyParams{.prediction_sigma_m = std::nan("")}),
               std::invalid_argument);
}

}  // namespace
}  // namespace tumble
