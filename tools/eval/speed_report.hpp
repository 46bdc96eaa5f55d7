// `tumble-eval speed`: what tumbled costs, from the scan logs of replayed
// runs (per-stage time per scan, whole-pipeline percentiles, latency), the
// replay's multiple of real time, and the peak RSS of each tumbled.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tools/eval/run_result.hpp"

namespace tumble::eval {

struct TimingStats {
  std::string name;  // stage name, "total" or "latency"
  std::size_t scans = 0;
  double mean_ms = 0.0;
  double p50_ms = 0.0;
  double p99_ms = 0.0;
  double max_ms = 0.0;
};

struct SpeedSummary {
  std::size_t runs = 0;             // tumbled runs that ended cleanly with a readable scan log
  std::size_t failed_runs = 0;      // the others
  std::vector<TimingStats> stages;  // in the scan log's column order
  std::optional<TimingStats> total;
  std::optional<TimingStats> latency;
  double replayed_s = 0.0;  // simulated time replayed
  double wall_s = 0.0;
  double slowest_realtime_multiple = 0.0;
  double peak_rss_mib = 0.0;          // largest over the runs
  std::vector<std::string> problems;  // "run variant: why" for the runs left out
};

// Mean, p50, p99 and max of one stage's times per scan.
TimingStats timing_stats(std::string name, std::vector<double> values_ms);
// "| name | mean | p50 | p99 | max |" (ms), one markdown table row.
std::string timing_row(const TimingStats& stats);

// scan_logs[i] belongs to results[i].
SpeedSummary summarize_speed(const std::vector<RunResult>& results,
                             const std::vector<std::filesystem::path>& scan_logs);

std::string speed_markdown(const SpeedSummary& summary, const std::string& heading);

}  // namespace tumble::eval
