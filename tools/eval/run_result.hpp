// The outcome of one job (run × model × de-skew) and how it is judged.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "tools/eval/bench_index.hpp"
#include "tools/eval/child_processes.hpp"
#include "tools/eval/drift.hpp"
#include "tools/eval/runaway.hpp"
#include "tools/eval/tumbled_job.hpp"

namespace tumble::eval {

// ok: evaluated. diverged: tumbled ran to the end but its trajectory is not a
// usable estimate (see DivergenceLimits). failed: the job could not be
// evaluated at all (missing or corrupt input, tumbled exited with an error or
// crashed, or its scan log shows it saw no scan or stopped seeing scans more
// than max_end_gap_s before the ground truth ends: a short recording); says
// nothing about the method.
enum class RunStatus { Ok, Diverged, Failed };
const char* to_string(RunStatus status);

// A run diverged when tumbled exited 0 but:
//  - fewer than 2 of its poses fall inside the ground truth's time span, or
//  - its last pose is more than max_end_gap_s before the ground truth ends
//    (registration stopped placing scans: the final error would be measured
//    at the wrong place), or
//  - its final error exceeds translation_cm_per_m (100 cm/m: an error as
//    large as the distance travelled) or rotation_deg_per_m, or is not finite.
// The paper's worst median (NM without de-skew) is 27 cm/m and 7 deg/m, so
// the limits only catch estimates that are lost, not ones that are poor.
struct DivergenceLimits {
  double translation_cm_per_m = 100.0;
  double rotation_deg_per_m = 45.0;
  double max_end_gap_s = 1.0;
};

struct EvalOptions {
  DriftOptions drift;
  DivergenceLimits limits;
};

struct RunResult {
  std::string run;
  std::string kind;
  double duration_s = 0.0;  // the run's simulated length
  Variant variant;
  RunStatus status = RunStatus::Failed;
  std::string message;  // why it failed or diverged; notes on an ok run
  std::optional<DriftResult> drift;
  std::size_t scans = 0;  // rows of the scan log
  std::size_t registered_scans = 0;
  // On ok and diverged runs alike: a run that diverged while published as
  // good is the worst case. None without a usable scan log with good_scan.
  std::optional<Runaway> runaway;
  ChildOutcome child;  // wall time, peak RSS
  std::filesystem::path trajectory;

  // Replay speed as a multiple of real time (NaN when tumbled did not run).
  double realtime_multiple() const;
};

RunResult failed_before_start(const BenchRun& run, const Variant& variant, std::string why);

// Judges a finished tumbled: reads the ground truth, the trajectory and the
// scan log. Never throws for bad files: they become a failed status.
RunResult evaluate_job(const BenchRun& run, const Variant& variant, const JobPaths& paths, const ChildOutcome& child,
                       const EvalOptions& options);

}  // namespace tumble::eval
