#include "tools/eval/speed_report.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <numeric>

#include "tools/eval/box_stats.hpp"
#include "tools/eval/scan_log.hpp"

namespace tumble::eval {

TimingStats timing_stats(std::string name, std::vector<double> values_ms) {
  TimingStats stats;
  stats.name = std::move(name);
  stats.scans = values_ms.size();
  if (values_ms.empty()) return stats;
  std::sort(values_ms.begin(), values_ms.end());
  stats.mean_ms = std::accumulate(values_ms.begin(), values_ms.end(), 0.0) / static_cast<double>(values_ms.size());
  stats.p50_ms = quantile_sorted(values_ms, 0.5);
  stats.p99_ms = quantile_sorted(values_ms, 0.99);
  stats.max_ms = values_ms.back();
  return stats;
}

std::string timing_row(const TimingStats& stats) {
  char text[160];
  std::snprintf(text, sizeof text, "| %s | %.3f | %.3f | %.3f | %.3f |\n", stats.name.c_str(), stats.mean_ms,
                stats.p50_ms, stats.p99_ms, stats.max_ms);
  return text;
}


SpeedSummary summarize_speed(const std::vector<RunResult>& results,
                             const std::vector<std::filesystem::path>& scan_logs) {
  SpeedSummary summary;
  std::vector<std::string> stage_names;
  std::vector<std::vector<double>> stage_values;
  std::vector<double> total, latency;
  summary.slowest_realtime_multiple = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < results.size(); ++i) {
    const RunResult& result = results[i];
    const std::string who = result.run + " " + result.variant.label() + ": ";
    if (!result.child.succeeded()) {
      ++summary.failed_runs;
      summary.problems.push_back(who + (result.message.empty() ? result.child.describe() : result.message));
      continue;
    }
    try {
      const ScanLog log = read_scan_log(scan_logs[i]);
      const std::vector<double>& run_total = log.column("total_ms");
      const std::vector<double>& run_latency = log.column("latency_ms");
      for (const std::string& stage : log.stage_columns()) {
        const auto it = std::find(stage_names.begin(), stage_names.end(), stage);
        std::size_t s = static_cast<std::size_t>(it - stage_names.begin());
        if (it == stage_names.end()) {
          stage_names.push_back(stage);
          stage_values.emplace_back();
        }
        const std::vector<double>& values = log.column(stage);
        stage_values[s].insert(stage_values[s].end(), values.begin(), values.end());
      }
      total.insert(total.end(), run_total.begin(), run_total.end());
      latency.insert(latency.end(), run_latency.begin(), run_latency.end());
    } catch (const std::exception& e) {
      ++summary.failed_runs;
      summary.problems.push_back(who + e.what());
      continue;
    }
    ++summary.runs;
    summary.replayed_s += result.duration_s;
    summary.wall_s += result.child.wall_s;
    summary.slowest_realtime_multiple = std::min(summary.slowest_realtime_multiple, result.realtime_multiple());
    summary.peak_rss_mib = std::max(summary.peak_rss_mib, static_cast<double>(result.child.peak_rss_kib) / 1024.0);
  }
  for (std::size_t s = 0; s < stage_names.size(); ++s) {
    std::string name = stage_names[s];
    name.resize(name.size() - 3);  // "_ms"
    summary.stages.push_back(timing_stats(name, std::move(stage_values[s])));
  }
  if (!total.empty()) summary.total = timing_stats("whole pipeline (total)", std::move(total));
  if (!latency.empty()) summary.latency = timing_stats("latency (scan complete → published)", std::move(latency));
  if (summary.runs == 0) summary.slowest_realtime_multiple = 0.0;
  return summary;
}

std::string speed_markdown(const SpeedSummary& summary, const std::string& heading) {
  std::string md = "# tumble-eval speed\n\n" + heading + "\n\n";
  char text[512];
  std::snprintf(text, sizeof text,
                "%zu runs replayed at --rate max (%zu left out): %.1f s of sensor time in %.1f s of wall time, "
                "%.2f× real time overall, slowest run %.2f×. Peak RSS of tumbled: %.1f MiB (largest run).\n\n",
                summary.runs, summary.failed_runs, summary.replayed_s, summary.wall_s,
                summary.wall_s > 0.0 ? summary.replayed_s / summary.wall_s : 0.0, summary.slowest_realtime_multiple,
                summary.peak_rss_mib);
  md += text;
  if (summary.total) {
    md += "Time per scan (ms; " + std::to_string(summary.total->scans) +
          " scans; the lidar's budget is 100 ms per scan at 10 Hz):\n\n";
    md += "| stage | mean | p50 | p99 | max |\n|---|---|---|---|---|\n";
    for (const TimingStats& stage : summary.stages) md += timing_row(stage);
    md += timing_row(*summary.total);
    if (summary.latency) md += timing_row(*summary.latency);
    md += "\n";
  }
  if (!summary.problems.empty()) {
    md += "Left out:\n\n";
    for (const std::string& problem : summary.problems) md += "- " + problem + "\n";
    md += "\n";
  }
  return md;
}

}  // namespace tumble::eval
