#include "tools/eval/run_result.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "tools/eval/scan_log.hpp"
#include "tools/eval/tum_file.hpp"

namespace tumble::eval {
namespace {

// tumbled's errors are one line; the last non-empty line of its output says why it stopped.
std::string last_line_of(const std::filesystem::path& log_path) {
  std::ifstream in(log_path);
  std::string line;
  std::string last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last;
}

std::string fixed(double value, int decimals) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(decimals);
  out << value;
  return out.str();
}

// Fills result.drift; returns why the run diverged, or "" when it did not.
std::string divergence(const PoseSeries& ground_truth, const PoseSeries& estimate, const EvalOptions& options,
                       RunResult& result) {
  try {
    result.drift = evaluate_drift(ground_truth, estimate, options.drift);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  const DriftResult& drift = *result.drift;
  const DivergenceLimits& limits = options.limits;
  const double end_gap_s = ground_truth.back().t_s - drift.last_t_s;
  if (end_gap_s > limits.max_end_gap_s)
    return "registration stopped " + fixed(end_gap_s, 1) + " s before the end of the run";
  if (!std::isfinite(drift.translation_cm_per_m) || !std::isfinite(drift.rotation_deg_per_m)) return "non-finite error";
  if (drift.translation_cm_per_m > limits.translation_cm_per_m)
    return "translation error " + fixed(drift.translation_cm_per_m, 1) + " cm/m > " +
           fixed(limits.translation_cm_per_m, 1);
  if (drift.rotation_deg_per_m > limits.rotation_deg_per_m)
    return "rotation error " + fixed(drift.rotation_deg_per_m, 1) + " deg/m > " + fixed(limits.rotation_deg_per_m, 1);
  return "";
}

}  // namespace

const char* to_string(RunStatus status) {
  switch (status) {
    case RunStatus::Ok:
      return "ok";
    case RunStatus::Diverged:
      return "diverged";
    case RunStatus::Failed:
      return "failed";
  }
  return "?";
}

double RunResult::realtime_multiple() const {
  if (!child.start_error.empty() || !(child.wall_s > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return duration_s / child.wall_s;
}

RunResult failed_before_start(const BenchRun& run, const Variant& variant, std::string why) {
  RunResult result;
  result.run = run.name;
  result.kind = run.kind;
  result.duration_s = run.duration_s;
  result.variant = variant;
  result.status = RunStatus::Failed;
  result.message = std::move(why);
  result.child.start_error = "not started";
  return result;
}

RunResult evaluate_job(const BenchRun& run, const Variant& variant, const JobPaths& paths, const ChildOutcome& child,
                       const EvalOptions& options) {
  RunResult result = failed_before_start(run, variant, "");
  result.child = child;
  if (!child.succeeded()) {
    const std::string said = child.start_error.empty() ? last_line_of(paths.log) : "";
    result.message = "tumbled: " + child.describe() + (said.empty() ? "" : ": " + said);
    return result;
  }

  PoseSeries ground_truth;
  PoseSeries estimate;
  try {
    ground_truth = read_tum(run.dir / "ground_truth.tum");
    if (ground_truth.size() < 2)
      throw std::runtime_error((run.dir / "ground_truth.tum").string() + ": fewer than 2 poses");
  } catch (const std::exception& e) {
    result.message = std::string("ground truth: ") + e.what();
    return result;
  }
  try {
    estimate = read_tum(paths.trajectory);
    result.trajectory = paths.trajectory;
  } catch (const std::exception& e) {
    result.message = std::string("trajectory: ") + e.what();
    return result;
  }
  // The scan log tells a short input from a lost estimate: it has a row for
  // every scan tumbled saw, placed or not. A bad one is noted and the run is
  // still judged from its trajectory.
  std::string scan_log_note;
  try {
    const ScanLog log = read_scan_log(paths.scan_log);
    const std::vector<double>& registered = log.column("registered");
    const std::vector<double>& scan_times_s = log.column("t_s");
    result.scans = log.scans();
    for (const double flag : registered) result.registered_scans += flag != 0.0 ? 1 : 0;
    const double input_gap_s =
        scan_times_s.empty() ? 0.0
                             : ground_truth.back().t_s - *std::max_element(scan_times_s.begin(), scan_times_s.end());
    if (result.scans == 0 || input_gap_s > options.limits.max_end_gap_s) {
      result.message =
          (result.scans == 0 ? std::string("tumbled processed no scan")
                             : "tumbled's last scan is " + fixed(input_gap_s, 1) + " s before the ground truth ends") +
          " (short or corrupt recording? see " + paths.log.string() + ")";
      return result;
    }
    result.runaway = runaway_of(ground_truth, estimate, log);
  } catch (const std::exception& e) {
    scan_log_note = std::string("scan log unusable: ") + e.what();
  }
  result.message = divergence(ground_truth, estimate, options, result);
  result.status = result.message.empty() ? RunStatus::Ok : RunStatus::Diverged;
  if (!scan_log_note.empty()) result.message += (result.message.empty() ? "" : "; ") + scan_log_note;
  return result;
}

}  // namespace tumble::eval
