// The runaway figure: how far a pose runs away while tumbled publishes every
// scan as good. A pose tumbled calls bad is one the robot can act on; a wrong
// pose it vouches for is the worst failure it can have.
//
// Per registered scan with an estimated pose, its position error
// ‖p_est − p_gt‖, the estimate aligned to ground truth at its first pose (as
// drift.hpp). A good stretch is a maximal run of consecutive such scans, in the
// scan log's order, all with good_scan = 1: a scan judged not good, or not
// registered, ends it. Its growth is the largest rise of the error inside it,
// max over i ≤ j of e_j − e_i: an error the pose already had when tumbled
// called it good again is not counted, only what grew while it vouched.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "tools/eval/pose_series.hpp"
#include "tools/eval/scan_log.hpp"

namespace tumble::eval {

// The acceptance bar: no good stretch may grow more than this.
constexpr double kRunawayLimit_m = 0.5;

struct ScanVerdict {
  double t_s = 0.0;   // since the run's first pose
  bool good = false;  // registered and good_scan = 1
  // None where the trajectory has no pose at the scan's time inside the
  // ground truth: such a scan neither ends a stretch (it is no verdict) nor
  // joins it.
  std::optional<double> position_error_m;
};

struct GoodStretch {
  double start_s = 0.0;  // its first and last scan, since the run's first pose
  double end_s = 0.0;
  std::size_t scans = 0;  // with a position error
  double growth_m = 0.0;
};

struct Runaway {
  std::size_t scans = 0;           // rows of the scan log
  std::size_t not_good_scans = 0;  // good_scan = 0, or not registered
  std::size_t stretches_over_limit = 0;
  std::optional<GoodStretch> largest;  // the stretch that grew most; none without a good scan with a pose

  double growth_m() const { return largest ? largest->growth_m : 0.0; }
};

// One verdict per row of the log; it needs t_s, registered and good_scan.
std::vector<ScanVerdict> scan_verdicts(const PoseSeries& ground_truth, const PoseSeries& estimate, const ScanLog& log);

Runaway find_runaway(const std::vector<ScanVerdict>& scans, double limit_m = kRunawayLimit_m);

// None when the log has no good_scan column (written by a tumbled before it).
std::optional<Runaway> runaway_of(const PoseSeries& ground_truth, const PoseSeries& estimate, const ScanLog& log);

// "0.620 m over 12.3–18.9 s (66 scans)": the largest growth and where it is.
std::string largest_growth_text(const Runaway& runaway);

}  // namespace tumble::eval
