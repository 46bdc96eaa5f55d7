// tumble-eval integrity: tumbled's expected error (the scan log's
// expected_error_m, registration_t.expected_error_m) scored as a detector of
// wrong poses, and its published position covariance checked for consistency
// (NEES), against ground truth.
//
// Truth, per registered scan (the one that started a map excluded):
// - the error of its pose increment from the previous registered scan, and
//   from the registered scan `window` scans back (a slip shows over ~1 s);
// - that one-scan error against the two poses' published position
//   covariances: NEES per degree of freedom, eᵀ(P_a + P_b)⁻¹e / 3, with e in W.
// Per run: its error, the final one in cm/m, or for a run of kind `long` (which
// ends where it started) the RPE over 10 m of travel; and its runaway.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "tools/eval/pose_series.hpp"
#include "tools/eval/runaway.hpp"
#include "tools/eval/scan_log.hpp"

namespace tumble::eval {

struct ScanIntegrity {
  double expected_error_m = 0.0;
  double increment_error_m = 0.0;  // from the previous registered scan
  double window_error_m = 0.0;     // from the registered scan `window` scans back; NaN for the first ones
  double nees_per_dof = 0.0;       // NaN when a covariance is not finite or singular
  // tumbled's own verdict (the scan log's good_scan): false where the scan put
  // it in `degraded`, for any reason. Absent from logs written before it.
  std::optional<bool> good_scan;
};

// The scan log needs t_s, registered, iterations, expected_error_m and the
// published position covariance (cov_txx, cov_tyy, cov_tzz, cov_txy, cov_txz,
// cov_tyz); good_scan is read where present. Scans without an estimated pose
// at their time are skipped.
std::vector<ScanIntegrity> score_scans(const PoseSeries& ground_truth, const PoseSeries& estimate, const ScanLog& log,
                                       std::size_t window = 10);

struct RunIntegrity {
  std::string name;
  double error_cm_per_m = 0.0;  // the run's error (header): what "run over 2 cm/m" judges
  double distance_m = 0.0;
  std::vector<ScanIntegrity> scans;
  std::optional<Runaway> runaway = std::nullopt;  // none without a scan log with good_scan
};

struct DetectorLimits {
  double good_run_cm_per_m = 0.5;  // false alarms are counted on runs under this
  double bad_run_cm_per_m = 2.0;   // a run over this should be flagged somewhere
  double slipped_m = 0.2;          // a scan whose window error is over this should be flagged
  double good_run_flag_share = 0.02;
};

// One markdown report: per threshold, the detector's figures, and the same
// figures for tumbled's verdict where every scan has one; then the NEES; then
// the runs' runaway (runaway.hpp): the largest, and every run over the bar.
std::string integrity_markdown(const std::vector<RunIntegrity>& runs, const std::vector<double>& thresholds_m,
                               const DetectorLimits& limits = {});

}  // namespace tumble::eval
