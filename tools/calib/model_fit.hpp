// Fits of the paper's speed-uncertainty models (§V-A) to the third quartile of
// the per-bin σ's, by least squares on σ itself (unweighted):
//  - log-normal σ_v(v) = λ / (β v √(2π)) · exp(−ln²(v/κ) / (2β²)): λ enters
//    linearly, so a grid over (β, κ) with the best λ in closed form gives the
//    start, then Levenberg–Marquardt refines all three, each mapped into the
//    range config/tumbled.yaml accepts (a falling curve wants κ → ∞: the fit
//    then lies on the range's edge, and says so); the model is evaluated by
//    the core's own function;
//  - cubic σ_ω(ω) = (ω/φ)³ is linear in c = φ⁻³: closed form, clamped to the
//    config range (and says so).
#pragma once

#include <span>
#include <string>

namespace tumble::calib {

// Ranges of config/tumbled.yaml (daemon/config.cpp).
inline constexpr double kBetaMin = 0.01, kBetaMax = 10;
inline constexpr double kKappaMin_m_s = 0.01, kKappaMax_m_s = 100;
inline constexpr double kLambdaMin = 0, kLambdaMax = 100;
inline constexpr double kPhiMin_rad_s = 0.01, kPhiMax_rad_s = 1000;

struct LognormalFit {
  bool fitted = false;  // false: too few points or nothing above zero; the values are then the paper's
  double beta = 1.1;
  double kappa_m_s = 1.9;
  double lambda = 0.222;
  double rms_error_m_s = 0;  // of the fit at the data points
  std::string note;          // why not fitted, or which parameter hit its range
};

struct CubicFit {
  bool fitted = false;
  double phi_rad_s = 16;
  double rms_error_rad_s = 0;
  std::string note;
};

double lognormal_sigma(double speed_m_s, double beta, double kappa_m_s, double lambda);
double cubic_sigma(double rate_rad_s, double phi_rad_s);

// speeds > 0; sigmas may be ≤ 0 (noise below the zero-speed offset).
LognormalFit fit_lognormal(std::span<const double> speeds_m_s, std::span<const double> sigmas_m_s);
CubicFit fit_cubic(std::span<const double> rates_rad_s, std::span<const double> sigmas_rad_s);

}  // namespace tumble::calib
