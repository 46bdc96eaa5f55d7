// From per-scan residuals to fitted models: the noise offset, the paper's
// conversions, the third quartile, the fit, and the check against the true
// de-skew error — on synthetic scans whose speed uncertainty is known.
#include "tools/calib/axis_calibration.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace tumble::calib {
namespace {

constexpr double kTau_s = 0.1;
constexpr double kRange_m = 10.0;
constexpr double kNoiseOffset_m = 0.012;  // mean residual of the noise alone
constexpr double kNoiseRms_m = 0.015;     // its RMS
constexpr int kScansPerBin = 41;

// Per bin, the true σ of scan i is σ_model(speed) · u_i with u_i evenly spread
// over [0, 4/3]: its third quartile is exactly σ_model and its median 2/3 of
// it. The measured residual is built so that either noise removal gives the
// de-skew error back: mean = noise mean + r, RMS² = noise RMS² + (2r/√3)².
void set_measured(ScanRecord& s, double skew_m) {
  s.residual_m = kNoiseOffset_m + skew_m;
  s.residual_rms_m = std::sqrt(kNoiseRms_m * kNoiseRms_m + 4.0 / 3.0 * skew_m * skew_m);
}

std::vector<ScanRecord> synthetic_scans(Rig rig, const std::vector<double>& speeds, const auto& sigma_model) {
  std::vector<ScanRecord> scans;
  for (int i = 0; i < 10; ++i) {  // at rest: the noise alone (the first ones before any motion)
    ScanRecord s;
    s.duration_s = kTau_s;
    s.mean_range_m = kRange_m;
    s.deskew_error_m = i < 4 ? 0.0 : 0.01;  // rest after a motion carries some skew
    set_measured(s, s.deskew_error_m);
    s.before_motion = i < 4;
    scans.push_back(s);
  }
  for (const double v : speeds) {
    for (int i = 0; i < kScansPerBin; ++i) {
      ScanRecord s;
      s.speed = v * (1 + 0.01 * (i % 3 - 1));  // scans near, not at, the nominal speed; median at it
      s.duration_s = kTau_s;
      s.mean_range_m = kRange_m;
      const double u = (4.0 / 3.0) * i / (kScansPerBin - 1);
      s.deskew_error_m = residual_from_sigma(rig, sigma_model(v) * u, kTau_s, kRange_m);
      set_measured(s, s.deskew_error_m);
      s.saturated = rig == Rig::Turntable && v > 7.85;
      scans.push_back(s);
    }
  }
  return scans;
}

TEST(AxisCalibration, ConvertsWithThePapersEquations) {
  // r_v ≈ σ_v τ/2 and r_ω ≈ σ_ω τ d/2.
  EXPECT_DOUBLE_EQ(sigma_from_residual(Rig::Rail, 0.005, 0.1, 7.0), 0.1);
  EXPECT_DOUBLE_EQ(sigma_from_residual(Rig::Turntable, 0.05, 0.1, 10.0), 0.1);
  EXPECT_DOUBLE_EQ(residual_from_sigma(Rig::Turntable, 0.1, 0.1, 10.0), 0.05);
  EXPECT_THROW(sigma_from_residual(Rig::Rail, 0.005, 0.0, 7.0), std::invalid_argument);
  EXPECT_THROW(sigma_from_residual(Rig::Turntable, 0.005, 0.1, 0.0), std::invalid_argument);
}

TEST(AxisCalibration, RecoversTheLognormalModelFromRailResiduals) {
  const std::vector<double> speeds{0.25, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5};
  const auto model = [](double v) { return lognormal_sigma(v, 0.9, 1.2, 0.15); };
  const std::vector<ScanRecord> scans = synthetic_scans(Rig::Rail, speeds, model);
  std::vector<double> nominal(speeds);
  const AxisCalibration axis = calibrate_axis(Rig::Rail, scans, bin_centres(nominal));

  EXPECT_EQ(axis.scans, scans.size());
  EXPECT_EQ(axis.noise.removal, NoiseRemoval::Quadrature);
  EXPECT_EQ(axis.noise.scans, 4u);  // only the rest before motion
  EXPECT_DOUBLE_EQ(axis.noise.mean_m, kNoiseOffset_m);
  EXPECT_DOUBLE_EQ(axis.noise.rms_m, kNoiseRms_m);
  ASSERT_EQ(axis.bins.size(), speeds.size() + 1);
  EXPECT_FALSE(axis.bins[0].in_fit);
  EXPECT_EQ(axis.bins[0].scans, 10u);
  for (std::size_t b = 1; b < axis.bins.size(); ++b) {
    const BinSummary& bin = axis.bins[b];
    SCOPED_TRACE(bin.centre);
    EXPECT_TRUE(bin.in_fit);
    EXPECT_EQ(bin.scans, static_cast<std::size_t>(kScansPerBin));
    EXPECT_DOUBLE_EQ(bin.speed_median, bin.centre);
    EXPECT_NEAR(bin.sigma.q3, model(bin.centre), 1e-9);
    EXPECT_NEAR(bin.deskew_sigma.q3, model(bin.centre), 1e-12);
    EXPECT_NEAR(bin.residual_m.median, kNoiseOffset_m + model(bin.centre) * (2.0 / 3.0) * kTau_s / 2, 1e-12);
  }
  ASSERT_TRUE(axis.lognormal.fitted);
  EXPECT_NEAR(axis.lognormal.beta, 0.9, 1e-4);
  EXPECT_NEAR(axis.lognormal.kappa_m_s, 1.2, 1e-4);
  EXPECT_NEAR(axis.lognormal.lambda, 0.15, 1e-5);
  // The check: a third-quartile curve bounds ~3/4 of the scans and predicts
  // 1.5× the median error (u's median is 2/3).
  EXPECT_NEAR(axis.bounded_fraction, 0.75, 0.04);
  EXPECT_NEAR(axis.predicted_over_true_median, 1.5, 0.05);
  EXPECT_NEAR(axis.model_over_true_q3_median, 1.0, 1e-4);
  for (std::size_t b = 1; b < axis.bins.size(); ++b)
    EXPECT_NEAR(axis.bins[b].model_sigma, model(axis.bins[b].centre), 1e-6);
}

TEST(AxisCalibration, RecoversTheCubicModelFromTurntableResiduals) {
  const std::vector<double> rates{0.5, 1, 2, 3, 4, 5, 6, 8, 10, 11};
  const auto model = [](double w) { return cubic_sigma(w, 12.0); };
  const std::vector<ScanRecord> scans = synthetic_scans(Rig::Turntable, rates, model);
  const AxisCalibration axis = calibrate_axis(Rig::Turntable, scans, bin_centres(rates));
  ASSERT_TRUE(axis.cubic.fitted);
  EXPECT_NEAR(axis.cubic.phi_rad_s, 12.0, 1e-9);
  EXPECT_NEAR(axis.bounded_fraction, 0.75, 0.04);
  EXPECT_EQ(axis.bins.back().saturated_scans, static_cast<std::size_t>(kScansPerBin));
}

TEST(AxisCalibration, ThePapersSubtractionRecoversTheModelTooWhenSkewAddsToTheMean) {
  const std::vector<double> rates{0.5, 1, 2, 3, 4, 5, 6, 8, 10, 11};
  const auto model = [](double w) { return cubic_sigma(w, 12.0); };
  const std::vector<ScanRecord> scans = synthetic_scans(Rig::Turntable, rates, model);
  const AxisCalibration axis =
      calibrate_axis(Rig::Turntable, scans, bin_centres(rates), AxisOptions{.noise_removal = NoiseRemoval::Subtract});
  EXPECT_NEAR(axis.cubic.phi_rad_s, 12.0, 1e-9);
  ScanRecord s;
  s.residual_m = 0.010;  // below the noise: a negative skew residual, kept (quartiles stay unbiased)
  s.residual_rms_m = 0.012;
  EXPECT_DOUBLE_EQ(axis.noise.skew_residual_m(s), 0.010 - kNoiseOffset_m);
  NoiseFloor quadrature = axis.noise;
  quadrature.removal = NoiseRemoval::Quadrature;
  EXPECT_DOUBLE_EQ(quadrature.skew_residual_m(s),
                   -std::sqrt(3.0) / 2 * std::sqrt(kNoiseRms_m * kNoiseRms_m - 0.012 * 0.012));
}

TEST(AxisCalibration, SparseBinsStayOutOfTheFitAndNaNScansAreIgnored) {
  const std::vector<double> rates{1, 2, 4, 8};
  const auto model = [](double w) { return cubic_sigma(w, 10.0); };
  std::vector<ScanRecord> scans = synthetic_scans(Rig::Turntable, rates, model);
  ScanRecord lonely;  // a bin of 2 scans (below min_scans_per_bin = 3) with a wild value
  lonely.speed = 16;
  lonely.duration_s = kTau_s;
  lonely.mean_range_m = kRange_m;
  set_measured(lonely, 50);
  scans.push_back(lonely);
  scans.push_back(lonely);
  ScanRecord empty = lonely;  // no point qualified
  empty.residual_m = std::nan("");
  scans.push_back(empty);
  std::vector<double> nominal(rates);
  nominal.push_back(16);
  const AxisCalibration axis = calibrate_axis(Rig::Turntable, scans, bin_centres(nominal));
  EXPECT_EQ(axis.scans, scans.size() - 1);
  EXPECT_FALSE(axis.bins.back().in_fit);
  EXPECT_EQ(axis.bins.back().scans, 2u);
  EXPECT_NEAR(axis.cubic.phi_rad_s, 10.0, 1e-9);
}

TEST(AxisCalibration, WithoutRestBeforeMotionAllRestScansGiveTheOffset) {
  std::vector<ScanRecord> scans = synthetic_scans(Rig::Rail, {1.0}, [](double) { return 0.1; });
  for (ScanRecord& s : scans) s.before_motion = false;
  const AxisCalibration axis = calibrate_axis(Rig::Rail, scans, bin_centres(std::vector<double>{1.0}));
  EXPECT_EQ(axis.noise.scans, 10u);
  EXPECT_DOUBLE_EQ(axis.noise.mean_m, kNoiseOffset_m + 0.01);  // the median of 4 × 0 and 6 × 0.01 extra
  EXPECT_FALSE(axis.lognormal.fitted);                         // one moving bin cannot fix three parameters
}

}  // namespace
}  // namespace tumble::calib
