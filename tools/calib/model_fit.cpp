#include "tools/calib/model_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/speed_uncertainty.hpp"
#include "tools/calib/least_squares.hpp"

namespace tumble::calib {
namespace {

void require_same_size(std::size_t a, std::size_t b) {
  if (a != b) throw std::invalid_argument("model fit: speeds and sigmas differ in size");
}

double rms_of(std::span<const double> x, std::span<const double> y, const auto& model) {
  double sum = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sum += std::pow(model(x[i]) - y[i], 2);
  return x.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(x.size()));
}

// The λ that best fits y for the shape g (σ = λ·g): Σ g y / Σ g².
double best_gain(std::span<const double> speeds, std::span<const double> sigmas, double beta, double kappa) {
  double gy = 0, gg = 0;
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    const double g = lognormal_sigma(speeds[i], beta, kappa, 1.0);
    gy += g * sigmas[i];
    gg += g * g;
  }
  return gg > 0 ? std::max(0.0, gy / gg) : 0.0;
}

// A parameter confined to [lo, hi] (both > 0) through y ∈ ℝ.
struct LogRange {
  double lo, hi;
  double span() const { return std::log(hi) - std::log(lo); }
  // Clamped: exp(log(hi)) may round above hi, which the config would refuse.
  double value(double y) const { return std::clamp(std::exp(std::log(lo) + span() * (1 + std::tanh(y)) / 2), lo, hi); }
  double log_derivative(double y) const { return span() * (1 - std::tanh(y) * std::tanh(y)) / 2; }  // d ln p / dy
  double inverse(double p) const {
    const double u = 2 * (std::log(std::clamp(p, lo, hi)) - std::log(lo)) / span() - 1;
    return std::atanh(std::clamp(u, -1 + 1e-9, 1 - 1e-9));
  }
};

// λ's config minimum is 0, which a log cannot reach; below this the curve is 0 for any purpose.
constexpr double kLambdaFitMin = 1e-9;

void note_if_at_bound(double value, const LogRange& range, const char* name, std::string& note) {
  if (value > range.lo * 1.001 && value < range.hi / 1.001) return;
  note += std::string(note.empty() ? "" : "; ") + name + " at the end of its config range [" +
          std::to_string(range.lo) + ", " + std::to_string(range.hi) + "]";
}

void clamp_noting(double& value, double lo, double hi, const char* name, std::string& note) {
  if (value >= lo && value <= hi) return;
  value = std::clamp(value, lo, hi);
  note += std::string(note.empty() ? "" : "; ") + name + " clamped to the config range [" + std::to_string(lo) + ", " +
          std::to_string(hi) + "]";
}

}  // namespace

double lognormal_sigma(double speed_m_s, double beta, double kappa_m_s, double lambda) {
  SpeedUncertaintyParams p;
  p.lognormal_shape_beta = beta;
  p.lognormal_scale_kappa_m_s = kappa_m_s;
  p.lognormal_gain_lambda = lambda;
  return lognormal_linear_sigma(speed_m_s, p);
}

double cubic_sigma(double rate_rad_s, double phi_rad_s) {
  SpeedUncertaintyParams p;
  p.cubic_scale_phi_rad_s = phi_rad_s;
  return cubic_angular_sigma(rate_rad_s, p);
}

LognormalFit fit_lognormal(std::span<const double> speeds, std::span<const double> sigmas) {
  require_same_size(speeds.size(), sigmas.size());
  LognormalFit fit;
  if (speeds.size() < 3) {
    fit.note = "fewer than 3 speed bins: not fitted";
    return fit;
  }
  if (std::any_of(speeds.begin(), speeds.end(), [](double v) { return !(v > 0); }))
    throw std::invalid_argument("fit_lognormal: speeds must be > 0");
  if (*std::max_element(sigmas.begin(), sigmas.end()) <= 0) {
    fit.note = "no speed uncertainty above the zero-speed offset: not fitted";
    return fit;
  }

  // Start: grid over the shape, the gain in closed form.
  const auto [v_min, v_max] = std::minmax_element(speeds.begin(), speeds.end());
  double best_cost = std::numeric_limits<double>::infinity();
  double beta0 = 1, kappa0 = 1, lambda0 = 0;
  constexpr int kKappaSteps = 40;
  for (const double beta : {0.2, 0.35, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0}) {
    for (int k = 0; k <= kKappaSteps; ++k) {
      const double kappa =
          std::clamp(*v_min / 10 * std::pow(100 * *v_max / *v_min, static_cast<double>(k) / kKappaSteps), kKappaMin_m_s,
                     kKappaMax_m_s);
      const double lambda = best_gain(speeds, sigmas, beta, kappa);
      double cost = 0;
      for (std::size_t i = 0; i < speeds.size(); ++i)
        cost += std::pow(lognormal_sigma(speeds[i], beta, kappa, lambda) - sigmas[i], 2);
      if (lambda > 0 && cost < best_cost) {
        best_cost = cost;
        beta0 = beta;
        kappa0 = kappa;
        lambda0 = lambda;
      }
    }
  }

  // Refine y with ln p = a + (b − a)(1 + tanh y)/2 per parameter, [a, b] the
  // logs of its config range: the optimum stays inside the range instead of
  // being clamped afterwards (the fit along the range's edge is then still a
  // fit). With L = ln(v/κ): ∂σ/∂ln β = σ (L²/β² − 1), ∂σ/∂ln κ = σ L/β²,
  // ∂σ/∂ln λ = σ.
  const LogRange ranges[3] = {{kBetaMin, kBetaMax}, {kKappaMin_m_s, kKappaMax_m_s}, {kLambdaFitMin, kLambdaMax}};
  const ResidualFunction residuals = [&](const Eigen::VectorXd& y, Eigen::VectorXd& r, Eigen::MatrixXd& J) {
    const double beta = ranges[0].value(y(0)), kappa = ranges[1].value(y(1)), lambda = ranges[2].value(y(2));
    const auto m = static_cast<Eigen::Index>(speeds.size());
    r.resize(m);
    J.resize(m, 3);
    for (Eigen::Index i = 0; i < m; ++i) {
      const double v = speeds[static_cast<std::size_t>(i)];
      const double s = lognormal_sigma(v, beta, kappa, lambda);
      const double L = std::log(v / kappa);
      r(i) = s - sigmas[static_cast<std::size_t>(i)];
      J(i, 0) = s * (L * L / (beta * beta) - 1) * ranges[0].log_derivative(y(0));
      J(i, 1) = s * L / (beta * beta) * ranges[1].log_derivative(y(1));
      J(i, 2) = s * ranges[2].log_derivative(y(2));
    }
  };
  const Eigen::Vector3d y0(ranges[0].inverse(beta0), ranges[1].inverse(kappa0), ranges[2].inverse(lambda0));
  const LeastSquaresResult lm = levenberg_marquardt(residuals, y0);
  fit.beta = ranges[0].value(lm.x(0));
  fit.kappa_m_s = ranges[1].value(lm.x(1));
  fit.lambda = ranges[2].value(lm.x(2));
  if (!lm.converged) fit.note = "Levenberg-Marquardt stopped at its iteration limit";
  note_if_at_bound(fit.beta, ranges[0], "beta", fit.note);
  note_if_at_bound(fit.kappa_m_s, ranges[1], "kappa", fit.note);
  note_if_at_bound(fit.lambda, ranges[2], "lambda", fit.note);
  fit.rms_error_m_s =
      rms_of(speeds, sigmas, [&](double v) { return lognormal_sigma(v, fit.beta, fit.kappa_m_s, fit.lambda); });
  fit.fitted = true;
  return fit;
}

CubicFit fit_cubic(std::span<const double> rates, std::span<const double> sigmas) {
  require_same_size(rates.size(), sigmas.size());
  CubicFit fit;
  if (rates.empty()) {
    fit.note = "no angular speed bin: not fitted";
    return fit;
  }
  double w3s = 0, w6 = 0;
  for (std::size_t i = 0; i < rates.size(); ++i) {
    const double w3 = std::pow(std::abs(rates[i]), 3);
    w3s += w3 * sigmas[i];
    w6 += w3 * w3;
  }
  if (!(w3s > 0) || !(w6 > 0)) {
    fit.note = "no angular speed uncertainty above the zero-speed offset: not fitted";
    return fit;
  }
  fit.phi_rad_s = std::cbrt(w6 / w3s);  // c = Σ ω³σ / Σ ω⁶, φ = c^(−1/3)
  clamp_noting(fit.phi_rad_s, kPhiMin_rad_s, kPhiMax_rad_s, "phi", fit.note);
  fit.rms_error_rad_s = rms_of(rates, sigmas, [&](double w) { return cubic_sigma(w, fit.phi_rad_s); });
  fit.fitted = true;
  return fit;
}

}  // namespace tumble::calib
