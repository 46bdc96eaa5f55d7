#include "tools/calib/axis_calibration.hpp"

#include <cmath>
#include <stdexcept>

namespace tumble::calib {
namespace {

struct BinScans {
  std::vector<const ScanRecord*> scans;
};

// Fills the proof fields of a bin (or of all moving scans) from its scans.
void compare_with_truth(const AxisCalibration& axis, std::span<const ScanRecord* const> scans, double& median_ratio,
                        double& bounded) {
  std::vector<double> ratios;
  std::size_t bounded_count = 0, compared = 0;
  for (const ScanRecord* s : scans) {
    if (!std::isfinite(s->deskew_error_m)) continue;
    const double predicted = residual_from_sigma(axis.rig, model_sigma(axis, s->speed), s->duration_s, s->mean_range_m);
    ++compared;
    if (s->deskew_error_m <= predicted) ++bounded_count;
    if (s->deskew_error_m > 0) ratios.push_back(predicted / s->deskew_error_m);
  }
  median_ratio = ratios.empty() ? std::nan("") : median(ratios);
  bounded = compared > 0 ? static_cast<double>(bounded_count) / static_cast<double>(compared) : std::nan("");
}

}  // namespace

double NoiseFloor::skew_residual_m(const ScanRecord& scan) const {
  if (removal == NoiseRemoval::Subtract) return scan.residual_m - mean_m;
  const double excess = scan.residual_rms_m * scan.residual_rms_m - rms_m * rms_m;
  return std::sqrt(3.0) / 2 * std::copysign(std::sqrt(std::abs(excess)), excess);
}

double sigma_from_residual(Rig rig, double residual_m, double duration_s, double mean_range_m) {
  if (!(duration_s > 0)) throw std::invalid_argument("sigma_from_residual: scan duration must be > 0");
  if (rig == Rig::Rail) return 2 * residual_m / duration_s;
  if (!(mean_range_m > 0)) throw std::invalid_argument("sigma_from_residual: mean range must be > 0");
  return 2 * residual_m / (duration_s * mean_range_m);
}

double residual_from_sigma(Rig rig, double sigma, double duration_s, double mean_range_m) {
  return rig == Rig::Rail ? sigma * duration_s / 2 : sigma * duration_s * mean_range_m / 2;
}

double model_sigma(const AxisCalibration& axis, double speed) {
  if (axis.rig == Rig::Rail)
    return lognormal_sigma(speed, axis.lognormal.beta, axis.lognormal.kappa_m_s, axis.lognormal.lambda);
  return cubic_sigma(speed, axis.cubic.phi_rad_s);
}

AxisCalibration calibrate_axis(Rig rig, std::span<const ScanRecord> scans, std::span<const double> centres,
                               const AxisOptions& options) {
  if (rig == Rig::Other) throw std::invalid_argument("calibrate_axis: rail or turntable");
  AxisCalibration axis;
  axis.rig = rig;
  std::vector<BinScans> binned(centres.size());
  for (const ScanRecord& s : scans) {
    if (!std::isfinite(s.residual_m) || !(s.duration_s > 0) || !(s.mean_range_m > 0)) continue;
    binned[bin_of(centres, s.speed)].scans.push_back(&s);
    ++axis.scans;
  }

  // The noise: rest before the rig first moved (all rest when no run has any).
  std::vector<const ScanRecord*> rest;
  for (const ScanRecord* s : binned[0].scans)
    if (s->before_motion) rest.push_back(s);
  if (rest.empty()) rest = binned[0].scans;
  axis.noise.removal = options.noise_removal;
  axis.noise.scans = rest.size();
  if (!rest.empty()) {
    std::vector<double> means, rms;
    for (const ScanRecord* s : rest) {
      means.push_back(s->residual_m);
      rms.push_back(s->residual_rms_m);
    }
    axis.noise.mean_m = median(means);
    axis.noise.rms_m = median(rms);
  }

  std::vector<double> fit_speeds, fit_sigmas;
  for (std::size_t b = 0; b < centres.size(); ++b) {
    const std::vector<const ScanRecord*>& in_bin = binned[b].scans;
    if (in_bin.empty()) continue;
    BinSummary bin;
    bin.centre = centres[b];
    bin.scans = in_bin.size();
    std::vector<double> speed, duration, range, residual, sigma, error, error_sigma;
    for (const ScanRecord* s : in_bin) {
      if (s->saturated) ++bin.saturated_scans;
      speed.push_back(s->speed);
      duration.push_back(s->duration_s);
      range.push_back(s->mean_range_m);
      residual.push_back(s->residual_m);
      sigma.push_back(sigma_from_residual(rig, axis.noise.skew_residual_m(*s), s->duration_s, s->mean_range_m));
      if (std::isfinite(s->deskew_error_m)) {
        error.push_back(s->deskew_error_m);
        error_sigma.push_back(sigma_from_residual(rig, s->deskew_error_m, s->duration_s, s->mean_range_m));
      }
    }
    bin.speed_median = median(speed);
    bin.duration_median_s = median(duration);
    bin.range_median_m = median(range);
    bin.residual_m = quartiles(residual);
    bin.sigma = quartiles(sigma);
    if (!error.empty()) {
      bin.deskew_error_m = quartiles(error);
      bin.deskew_sigma = quartiles(error_sigma);
    }
    bin.in_fit = b > 0 && bin.scans >= options.min_scans_per_bin && bin.speed_median > 0;
    if (bin.in_fit) {
      fit_speeds.push_back(bin.speed_median);
      fit_sigmas.push_back(bin.sigma.q3);
    }
    axis.bins.push_back(bin);
  }

  if (rig == Rig::Rail)
    axis.lognormal = fit_lognormal(fit_speeds, fit_sigmas);
  else
    axis.cubic = fit_cubic(fit_speeds, fit_sigmas);

  std::vector<const ScanRecord*> moving;
  std::size_t bin_slot = 0;
  for (std::size_t b = 0; b < centres.size(); ++b) {
    if (binned[b].scans.empty()) continue;
    BinSummary& bin = axis.bins[bin_slot++];
    bin.model_sigma = model_sigma(axis, bin.speed_median);
    if (b == 0) continue;  // σ(0) = 0 predicts nothing to compare
    bin.model_over_true_q3 = bin.deskew_sigma.q3 > 0 ? bin.model_sigma / bin.deskew_sigma.q3 : std::nan("");
    compare_with_truth(axis, binned[b].scans, bin.predicted_over_true_median, bin.bounded_fraction);
    moving.insert(moving.end(), binned[b].scans.begin(), binned[b].scans.end());
  }
  compare_with_truth(axis, moving, axis.predicted_over_true_median, axis.bounded_fraction);
  std::vector<double> model_over_q3;
  for (const BinSummary& bin : axis.bins)
    if (bin.centre > 0 && std::isfinite(bin.model_over_true_q3)) model_over_q3.push_back(bin.model_over_true_q3);
  axis.model_over_true_q3_median = model_over_q3.empty() ? std::nan("") : median(model_over_q3);
  return axis;
}

}  // namespace tumble::calib
