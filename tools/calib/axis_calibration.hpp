// From scan residuals to a fitted speed-uncertainty model for one axis kind
// (paper §V-A): linear from the rail, angular from the turntable.
//  1. bin the scans by true speed (speed_bins.hpp);
//  2. the noise (the paper's black dotted line) from the zero-speed scans
//     taken before the rig first moved. The paper takes "the residual at
//     0 m/s", assuming the odometry's error is negligible at rest; in this
//     pipeline it is not after a motion (the fused attitude keeps turning,
//     tools/calib/README.md), so rest after a motion would count skew as noise;
//  3. each scan's skew residual r (its residual without the noise):
//       subtract   — the paper's literal step: r = mean − mean₀;
//       quadrature — ours, the default: noise and skew add in squares, so
//                    r = (√3/2) · √(rms² − rms₀²), √3/2 being mean/RMS of an
//                    error growing linearly over the scan. Both agree when
//                    the skew dominates; when it is comparable with the
//                    noise (as in the simulator: ~1 cm vs 2 cm), |n + s|
//                    barely exceeds |n| on average and the subtraction
//                    reads a fraction of the skew (tools/calib/README.md);
//  4. convert with the paper's equations, with the scan's own τ (last −
//     first point time) and, for the angular one, its own mean range d:
//       σ_v = 2 r_v / τ          (r_v ≈ σ_v τ / 2)
//       σ_ω = 2 r_ω / (τ d)      (r_ω ≈ σ_ω τ d / 2);
//  5. fit the third quartile of σ per bin (bins above zero speed with at
//     least min_scans_per_bin scans, at the bin's median true speed):
//     log-normal for linear, cubic for angular (model_fit.hpp).
// The check against the simulator: each scan's noise-free de-skew error
// (scan_residual.hpp) is compared with what the fitted curve predicts for
// it, σ(speed)·τ/2 (·d): per bin the curve over the true third quartile
// (1 is perfect), the median ratio predicted/true over the scans, and the
// share of scans the prediction bounds (a perfect third-quartile fit: 75 %).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "tools/calib/bench_index.hpp"
#include "tools/calib/model_fit.hpp"
#include "tools/calib/run_evaluation.hpp"
#include "tools/calib/speed_bins.hpp"

namespace tumble::calib {

enum class NoiseRemoval { Quadrature, Subtract };

struct NoiseFloor {
  NoiseRemoval removal = NoiseRemoval::Quadrature;
  std::size_t scans = 0;  // rest scans it came from
  double mean_m = 0;      // median of their mean residuals (the paper's offset)
  double rms_m = 0;       // median of their RMS residuals

  // The part of a scan's residual due to skew (step 3); may be negative
  // when the scan's residual is below the noise.
  double skew_residual_m(const ScanRecord& scan) const;
};

struct BinSummary {
  double centre = 0;        // nominal speed, m/s or rad/s
  double speed_median = 0;  // median true speed of its scans
  std::size_t scans = 0;
  std::size_t saturated_scans = 0;
  double duration_median_s = 0;
  double range_median_m = 0;
  Quartiles residual_m;      // mean residual as measured, noise included (the paper's figure)
  Quartiles sigma;           // converted from the skew residual (m/s or rad/s)
  Quartiles deskew_error_m;  // noise-free, from the ground truth
  Quartiles deskew_sigma;    // the same converted (no noise to remove)
  bool in_fit = false;
  // The fitted model at this bin, and the check.
  double model_sigma = 0;
  double model_over_true_q3 = 0;          // the curve against the third quartile it should match
  double predicted_over_true_median = 0;  // median over the bin's scans of predicted / true de-skew error
  double bounded_fraction = 0;            // share of scans whose true de-skew error ≤ the prediction
};

struct AxisCalibration {
  Rig rig = Rig::Rail;
  std::size_t scans = 0;  // with a residual
  NoiseFloor noise;
  std::vector<BinSummary> bins;           // every non-empty bin, ascending speed
  LognormalFit lognormal;                 // rail
  CubicFit cubic;                         // turntable
  double model_over_true_q3_median = 0;   // median over the moving bins
  double predicted_over_true_median = 0;  // over all moving scans
  double bounded_fraction = 0;
};

struct AxisOptions {
  NoiseRemoval noise_removal = NoiseRemoval::Quadrature;
  std::size_t min_scans_per_bin = 3;
};

// σ from a residual with the paper's equations (the rig picks which).
double sigma_from_residual(Rig rig, double residual_m, double duration_s, double mean_range_m);
// The de-skew error a σ predicts for a scan: σ τ/2 or σ τ d/2.
double residual_from_sigma(Rig rig, double sigma, double duration_s, double mean_range_m);

// scans: every scan of the rig's runs. centres: bin_centres of its runs.
AxisCalibration calibrate_axis(Rig rig, std::span<const ScanRecord> scans, std::span<const double> centres,
                               const AxisOptions& options = {});

// The fitted model of the axis at a speed (σ_v or σ_ω).
double model_sigma(const AxisCalibration& axis, double speed);

}  // namespace tumble::calib
