#include "tools/eval/run_score.hpp"

#include <cmath>
#include <cstdio>

#include "tools/eval/scan_log.hpp"
#include "tools/eval/tum_file.hpp"

namespace tumble::eval {

namespace {

std::size_t count_true(const std::vector<double>& flags) {
  std::size_t n = 0;
  for (const double flag : flags) n += flag != 0.0 ? 1 : 0;
  return n;
}

std::string runaway_markdown(const std::optional<Runaway>& runaway) {
  if (!runaway) return "\nRunaway: not measured (the scan log has no good_scan column).\n";
  const double not_good_percent =
      runaway->scans > 0 ? 100.0 * static_cast<double>(runaway->not_good_scans) / static_cast<double>(runaway->scans)
                         : 0.0;
  char text[512];
  std::snprintf(text, sizeof text,
                "\nRunaway, the largest rise of the position error within a stretch of consecutive good scans "
                "(none may exceed %.1f m; times since the first pose):\n"
                "- %s; stretches over %.1f m: %zu; scans not good: %.2f %% of %zu\n",
                kRunawayLimit_m, largest_growth_text(*runaway).c_str(), kRunawayLimit_m,
                runaway->stretches_over_limit, not_good_percent, runaway->scans);
  return text;
}

}  // namespace

RunScore score_run(const std::filesystem::path& ground_truth, const std::filesystem::path& trajectory,
                   const std::optional<std::filesystem::path>& scan_log, const DriftOptions& options) {
  RunScore score;
  const PoseSeries truth = read_tum(ground_truth);
  const PoseSeries estimate = read_tum(trajectory);
  score.drift = evaluate_drift(truth, estimate, options);
  if (!scan_log) return score;
  const ScanLog log = read_scan_log(*scan_log);
  score.scans = log.scans();
  score.registered = count_true(log.column("registered"));
  score.converged = count_true(log.column("converged"));
  for (const std::string& stage : log.stage_columns())
    score.stages.push_back(timing_stats(stage.substr(0, stage.size() - 3), log.column(stage)));
  score.total = timing_stats("whole pipeline (total)", log.column("total_ms"));
  score.latency = timing_stats("latency (scan complete → published)", log.column("latency_ms"));
  score.runaway = runaway_of(truth, estimate, log);
  return score;
}

std::string score_markdown(const RunScore& score) {
  const DriftResult& d = score.drift;
  char text[768];
  std::snprintf(text, sizeof text,
                "Trajectory error against ground truth (%zu poses, %.1f s, %.2f m travelled):\n\n"
                "- final pose: %.2f cm → **%.2f cm/m**, %.3f deg → **%.3f deg/m**\n",
                d.poses, d.last_t_s - d.first_t_s, d.distance_m, d.final_translation_error_m * 100.0,
                d.translation_cm_per_m, d.final_rotation_error_deg, d.rotation_deg_per_m);
  std::string md = text;
  if (d.rpe_segments > 0 && std::isfinite(d.rpe_translation_cm_per_m)) {
    std::snprintf(text, sizeof text, "- RPE over %zu segments: %.2f cm/m, %.3f deg/m\n", d.rpe_segments,
                  d.rpe_translation_cm_per_m, d.rpe_rotation_deg_per_m);
    md += text;
  }
  if (!score.total) return md;
  std::snprintf(text, sizeof text,
                "\nScans: %zu, registered %zu, ICP converged %zu. Time per scan (ms elapsed; budget 100 ms at 10 Hz):\n\n",
                score.scans, score.registered, score.converged);
  md += text;
  md += "| stage | mean | p50 | p99 | max |\n|---|---|---|---|---|\n";
  for (const TimingStats& stage : score.stages) md += timing_row(stage);
  md += timing_row(*score.total);
  if (score.latency) md += timing_row(*score.latency);
  return md + runaway_markdown(score.runaway);
}

}  // namespace tumble::eval
