// The fits recover known parameters from synthetic third quartiles, and say
// when there is nothing to fit.
#include "tools/calib/model_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/speed_uncertainty.hpp"
#include "tools/calib/least_squares.hpp"

namespace tumble::calib {
namespace {

const std::vector<double> kRailSpeeds{0.25, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5};
const std::vector<double> kTurntableRates{0.5, 1, 2, 3, 4, 5, 6, 8, 10, 11};

TEST(LevenbergMarquardt, FitsAnExponentialDecay) {
  // y = a exp(−b t) with a = 2, b = 0.7, exact data.
  std::vector<double> t, y;
  for (int i = 0; i < 10; ++i) {
    t.push_back(0.5 * i);
    y.push_back(2.0 * std::exp(-0.7 * t.back()));
  }
  const ResidualFunction f = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r, Eigen::MatrixXd& J) {
    r.resize(10);
    J.resize(10, 2);
    for (int i = 0; i < 10; ++i) {
      const double e = std::exp(-x(1) * t[static_cast<std::size_t>(i)]);
      r(i) = x(0) * e - y[static_cast<std::size_t>(i)];
      J(i, 0) = e;
      J(i, 1) = -x(0) * t[static_cast<std::size_t>(i)] * e;
    }
  };
  const LeastSquaresResult result = levenberg_marquardt(f, Eigen::Vector2d(1.0, 0.1));
  EXPECT_TRUE(result.converged);
  EXPECT_NEAR(result.x(0), 2.0, 1e-8);
  EXPECT_NEAR(result.x(1), 0.7, 1e-8);
  EXPECT_LT(result.cost, 1e-20);
}

TEST(LognormalFit, RecoversThePapersParametersFromExactValues) {
  std::vector<double> sigmas;
  for (const double v : kRailSpeeds) sigmas.push_back(lognormal_sigma(v, 1.1, 1.9, 0.222));
  const LognormalFit fit = fit_lognormal(kRailSpeeds, sigmas);
  ASSERT_TRUE(fit.fitted);
  EXPECT_TRUE(fit.note.empty()) << fit.note;
  EXPECT_NEAR(fit.beta, 1.1, 1e-5);
  EXPECT_NEAR(fit.kappa_m_s, 1.9, 1e-4);
  EXPECT_NEAR(fit.lambda, 0.222, 1e-5);
  EXPECT_LT(fit.rms_error_m_s, 1e-9);
}

TEST(LognormalFit, MatchesTheCoresModelFunction) {
  SpeedUncertaintyParams p;
  p.lognormal_shape_beta = 0.6;
  p.lognormal_scale_kappa_m_s = 0.8;
  p.lognormal_gain_lambda = 0.05;
  for (const double v : {0.0, 0.3, 1.0, 3.0})
    EXPECT_DOUBLE_EQ(lognormal_sigma(v, 0.6, 0.8, 0.05), lognormal_linear_sigma(v, p));
}

TEST(LognormalFit, RecoversOtherShapesWithNoisyValues) {
  struct Case {
    double beta, kappa, lambda;
  };
  std::mt19937_64 rng(7);
  std::normal_distribution<double> relative_noise(0.0, 0.02);
  for (const Case c : {Case{0.5, 1.0, 0.05}, Case{1.5, 3.0, 0.4}, Case{0.8, 0.6, 0.1}}) {
    SCOPED_TRACE(testing::Message() << "beta " << c.beta << " kappa " << c.kappa << " lambda " << c.lambda);
    std::vector<double> speeds, sigmas;
    for (int i = 1; i <= 20; ++i) {
      speeds.push_back(0.2 * i);
      sigmas.push_back(lognormal_sigma(speeds.back(), c.beta, c.kappa, c.lambda) * (1 + relative_noise(rng)));
    }
    const LognormalFit fit = fit_lognormal(speeds, sigmas);
    ASSERT_TRUE(fit.fitted);
    EXPECT_NEAR(fit.beta, c.beta, 0.05 * c.beta);
    EXPECT_NEAR(fit.kappa_m_s, c.kappa, 0.05 * c.kappa);
    EXPECT_NEAR(fit.lambda, c.lambda, 0.05 * c.lambda);
  }
}

TEST(LognormalFit, AFallingCurveIsFittedAtTheEdgeOfTheConfigRange) {
  // bench1's rail third quartiles: falling over the whole speed range, so the
  // log-normal's peak wants to sit below the slowest bin with κ → ∞.
  const std::vector<double> sigmas{0.328, 0.268, 0.266, 0.255, 0.251, 0.232, 0.179, 0.152};
  const LognormalFit fit = fit_lognormal(kRailSpeeds, sigmas);
  ASSERT_TRUE(fit.fitted);
  EXPECT_LT(fit.rms_error_m_s, 0.03);
  EXPECT_LE(fit.kappa_m_s, kKappaMax_m_s);
  EXPECT_GE(fit.beta, kBetaMin);
  EXPECT_LE(fit.beta, kBetaMax);
  for (std::size_t i = 0; i < sigmas.size(); ++i)
    EXPECT_NEAR(lognormal_sigma(kRailSpeeds[i], fit.beta, fit.kappa_m_s, fit.lambda), sigmas[i], 0.06)
        << kRailSpeeds[i];
}

TEST(LognormalFit, TooFewBinsOrNothingAboveZeroIsNotFitted) {
  const std::vector<double> two{1.0, 2.0};
  LognormalFit fit = fit_lognormal(two, two);
  EXPECT_FALSE(fit.fitted);
  EXPECT_NE(fit.note.find("fewer than 3"), std::string::npos);
  const std::vector<double> zeros(kRailSpeeds.size(), 0.0);
  fit = fit_lognormal(kRailSpeeds, zeros);
  EXPECT_FALSE(fit.fitted);
  EXPECT_NE(fit.note.find("above the zero-speed offset"), std::string::npos);
  EXPECT_DOUBLE_EQ(fit.beta, 1.1);  // the paper's values stand
}

TEST(LognormalFit, NegativeValuesFromTheOffsetDoNotBreakTheFit) {
  std::vector<double> sigmas;
  for (const double v : kRailSpeeds) sigmas.push_back(lognormal_sigma(v, 1.1, 1.9, 0.222));
  sigmas.front() = -0.01;  // the slowest bin's residual below the noise offset
  const LognormalFit fit = fit_lognormal(kRailSpeeds, sigmas);
  ASSERT_TRUE(fit.fitted);
  EXPECT_GT(fit.lambda, 0.0);
  EXPECT_LT(fit.rms_error_m_s, 0.02);
}

TEST(CubicFit, RecoversPhiExactlyAndWithNoise) {
  std::vector<double> sigmas;
  for (const double w : kTurntableRates) sigmas.push_back(cubic_sigma(w, 16.0));
  CubicFit fit = fit_cubic(kTurntableRates, sigmas);
  ASSERT_TRUE(fit.fitted);
  EXPECT_NEAR(fit.phi_rad_s, 16.0, 1e-9);
  EXPECT_DOUBLE_EQ(cubic_sigma(8.0, 16.0), 0.125);

  std::mt19937_64 rng(3);
  std::normal_distribution<double> relative_noise(0.0, 0.05);
  for (double& s : sigmas) s *= 1 + relative_noise(rng);
  fit = fit_cubic(kTurntableRates, sigmas);
  EXPECT_NEAR(fit.phi_rad_s, 16.0, 0.4);
}

TEST(CubicFit, NothingAboveZeroIsNotFittedAndExtremesAreClamped) {
  const std::vector<double> zeros(kTurntableRates.size(), 0.0);
  EXPECT_FALSE(fit_cubic(kTurntableRates, zeros).fitted);
  EXPECT_FALSE(fit_cubic({}, {}).fitted);
  // A tiny uncertainty wants φ far above the config's 1000 rad/s.
  std::vector<double> tiny;
  for (const double w : kTurntableRates) tiny.push_back(cubic_sigma(w, 1e5));
  const CubicFit fit = fit_cubic(kTurntableRates, tiny);
  EXPECT_TRUE(fit.fitted);
  EXPECT_DOUBLE_EQ(fit.phi_rad_s, kPhiMax_rad_s);
  EXPECT_NE(fit.note.find("phi clamped"), std::string::npos);
}

TEST(ModelFit, MismatchedSizesThrow) {
  const std::vector<double> a{1, 2, 3}, b{1, 2};
  EXPECT_THROW(fit_lognormal(a, b), std::invalid_argument);
  EXPECT_THROW(fit_cubic(a, b), std::invalid_argument);
}

}  // namespace
}  // namespace tumble::calib
