// The paper's speed-uncertainty curves (§V-A) at its constants, checked against
// values worked out by hand, and the saturation bounds.
#include "core/speed_uncertainty.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace tumble {
namespace {

TEST(SpeedUncertainty, LognormalAtTheScaleIsTheGainOverBetaKappaRootTwoPi) {
  const SpeedUncertaintyParams p;
  // ln(κ/κ) = 0, so σ_v(κ) = λ / (β κ √(2π)) = 0.222 / (1.1 · 1.9 · 2.506628) = 0.042376.
  EXPECT_NEAR(lognormal_linear_sigma(1.9, p), 0.042376, 1e-6);
  // σ_v(2κ): 0.222/(1.1·3.8·2.506628) · exp(−ln²2 / 2.42) = 0.0211878 · 0.819923 = 0.017373.
  EXPECT_NEAR(lognormal_linear_sigma(3.8, p), 0.017373, 1e-6);
  EXPECT_DOUBLE_EQ(lognormal_linear_sigma(-1.9, p), lognormal_linear_sigma(1.9, p));
}

TEST(SpeedUncertainty, LognormalIsZeroAtRest) {
  const SpeedUncertaintyParams p;
  EXPECT_EQ(lognormal_linear_sigma(0.0, p), 0.0);
  EXPECT_LT(lognormal_linear_sigma(1e-3, p), 1e-6);
}

TEST(SpeedUncertainty, LognormalMaximumIsThePeakOfTheCurve) {
  const SpeedUncertaintyParams p;
  const double peak = lognormal_linear_sigma_max(p);
  // At v* = κ e^{−β²} = 0.5666 m/s: 0.077601 m/s.
  EXPECT_NEAR(peak, 0.077601, 1e-6);
  for (double v = 0.01; v < 20.0; v += 0.01) EXPECT_LE(lognormal_linear_sigma(v, p), peak + 1e-15) << v;
}

TEST(SpeedUncertainty, CubicAngularIsOneAtPhi) {
  const SpeedUncertaintyParams p;
  EXPECT_DOUBLE_EQ(cubic_angular_sigma(16.0, p), 1.0);
  EXPECT_DOUBLE_EQ(cubic_angular_sigma(8.0, p), 0.125);
  EXPECT_DOUBLE_EQ(cubic_angular_sigma(-16.0, p), 1.0);
  EXPECT_EQ(cubic_angular_sigma(0.0, p), 0.0);
}

TEST(SpeedUncertainty, WithoutDeskewSigmaIsProportionalToSpeed) {
  const SpeedUncertaintyParams p;
  EXPECT_DOUBLE_EQ(linear_speed_sigma(-2.0, false, false, p), 0.28);
  EXPECT_DOUBLE_EQ(angular_rate_sigma(3.0, false, false, p), 2.16);
  EXPECT_DOUBLE_EQ(linear_speed_sigma(2.0, false, true, p), lognormal_linear_sigma(2.0, p));
  EXPECT_DOUBLE_EQ(angular_rate_sigma(3.0, false, true, p), cubic_angular_sigma(3.0, p));
}

TEST(SpeedUncertainty, SaturatedAxisTakesTheLargestSigmaTheModelAllows) {
  const SpeedUncertaintyParams p;
  // Log-normal: its maximum, whatever the (clipped) speed says.
  EXPECT_DOUBLE_EQ(linear_speed_sigma(3.5, true, true, p), lognormal_linear_sigma_max(p));
  EXPECT_DOUBLE_EQ(linear_speed_sigma(0.0, true, true, p), lognormal_linear_sigma_max(p));
  // Cubic: at the platform's fastest rate (11 rad/s), not at the gyro's 7.85 rad/s clip.
  EXPECT_DOUBLE_EQ(angular_rate_sigma(7.85, true, true, p), std::pow(11.0 / 16.0, 3));
  // A clipped reading can exceed the range (the MTi reports −10.33 rad/s); keep the larger.
  EXPECT_DOUBLE_EQ(angular_rate_sigma(-12.0, true, true, p), std::pow(12.0 / 16.0, 3));
  EXPECT_DOUBLE_EQ(angular_rate_sigma(7.85, true, false, p), 0.72 * 11.0);
  EXPECT_DOUBLE_EQ(linear_speed_sigma(1.0, true, false, p), 0.14 * 3.5);
}

}  // namespace
}  // namespace tumble
