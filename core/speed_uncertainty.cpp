// See speed_uncertainty.hpp for the models and the saturation rule.
#include "core/speed_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tumble {

double lognormal_linear_sigma(double speed_m_s, const SpeedUncertaintyParams& p) {
  const double v = std::abs(speed_m_s);
  if (v == 0.0) return 0.0;  // the limit; ln(0) would give 0·∞
  const double beta = p.lognormal_shape_beta;
  const double log_ratio = std::log(v / p.lognormal_scale_kappa_m_s);
  return p.lognormal_gain_lambda / (beta * v * std::sqrt(2.0 * std::numbers::pi)) *
         std::exp(-log_ratio * log_ratio / (2.0 * beta * beta));
}

double lognormal_linear_sigma_max(const SpeedUncertaintyParams& p) {
  // d/dv [ln σ] = −1/v − ln(v/κ)/(β² v) = 0  ⇔  ln(v/κ) = −β².
  const double beta = p.lognormal_shape_beta;
  return lognormal_linear_sigma(p.lognormal_scale_kappa_m_s * std::exp(-beta * beta), p);
}

double cubic_angular_sigma(double rate_rad_s, const SpeedUncertaintyParams& p) {
  const double r = std::abs(rate_rad_s) / p.cubic_scale_phi_rad_s;
  return r * r * r;
}

double linear_speed_sigma(double speed_m_s, bool unknown, bool deskewed, const SpeedUncertaintyParams& p) {
  const double v = std::abs(speed_m_s);
  if (deskewed) return unknown ? lognormal_linear_sigma_max(p) : lognormal_linear_sigma(v, p);
  return p.raw_linear_gain * (unknown ? std::max(v, p.max_linear_speed_m_s) : v);
}

double angular_rate_sigma(double rate_rad_s, bool unknown, bool deskewed, const SpeedUncertaintyParams& p) {
  const double w = std::abs(rate_rad_s);
  const double effective = unknown ? std::max(w, p.max_angular_rate_rad_s) : w;
  return deskewed ? cubic_angular_sigma(effective, p) : p.raw_angular_gain * effective;
}

}  // namespace tumble
