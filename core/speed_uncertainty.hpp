// Speed-uncertainty models of the paper (§V-A): how wrong the odometry's
// per-axis speed estimate may be, as a function of that speed. They feed the
// VTW/GVTW perturbations δ = ∫σ_v dt and θ = ∫σ_ω dt (docs/method.md §3).
//
// Two pairs, because the error a weight model must cover depends on whether
// the scan was de-skewed:
//  - de-skewed: the residual error of the estimated velocity, fitted on the
//    rail/turntable data: log-normal σ_v(v) and cubic σ_ω(ω);
//  - not de-skewed: the motion itself is the skew, so σ is proportional to the
//    speed: σ_v = 0.14|v|, σ_ω = 0.72|ω| (the authors' implementation).
//
// Saturated axes (ours, see docs/method.md §1): when the IMU clips, the speed
// along that axis is not known, so the σ must not be the clipped speed's. We
// take the largest σ the model allows over the speeds the platform can reach:
//  - log-normal σ_v is bounded: its maximum over all v (at v* = κ·e^{−β²});
//  - the cubic σ_ω and the proportional models grow without bound, so they are
//    evaluated at max(|measured|, bound), the bound being the fastest the
//    platform is specified to move. Defaults are the paper's bench maxima
//    (11 rad/s — above the MTi-30's 7.85 rad/s gyro range — and 3.5 m/s).
#pragma once

namespace tumble {

struct SpeedUncertaintyParams {
  // Log-normal linear model σ_v(v) = λ/(β v √(2π)) · exp(−ln²(v/κ) / (2β²)).
  double lognormal_shape_beta = 1.1;
  double lognormal_scale_kappa_m_s = 1.9;
  double lognormal_gain_lambda = 0.222;
  // Cubic angular model σ_ω(ω) = (ω/φ)³.
  double cubic_scale_phi_rad_s = 16.0;
  // Without de-skewing: σ proportional to the speed.
  double raw_linear_gain = 0.14;
  double raw_angular_gain = 0.72;
  // Fastest the platform can move: where unbounded models are evaluated when
  // the IMU reports clipping on an axis.
  double max_linear_speed_m_s = 3.5;
  double max_angular_rate_rad_s = 11.0;
};

// σ_v of the de-skewed model at |speed_m_s|; 0 at 0.
double lognormal_linear_sigma(double speed_m_s, const SpeedUncertaintyParams& p);
// The maximum of lognormal_linear_sigma over all speeds (closed form).
double lognormal_linear_sigma_max(const SpeedUncertaintyParams& p);
// σ_ω of the de-skewed model at |rate_rad_s|.
double cubic_angular_sigma(double rate_rad_s, const SpeedUncertaintyParams& p);

// Per-axis σ as the weight models use it. `deskewed` selects the pair;
// `unknown` (IMU clipping on that axis) selects the bound described above.
double linear_speed_sigma(double speed_m_s, bool unknown, bool deskewed, const SpeedUncertaintyParams& p);
double angular_rate_sigma(double rate_rad_s, bool unknown, bool deskewed, const SpeedUncertaintyParams& p);

}  // namespace tumble
