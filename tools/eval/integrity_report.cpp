#include "tools/eval/integrity_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include <Eigen/Cholesky>

#include "tools/eval/box_stats.hpp"

namespace tumble::eval {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
struct RegisteredScan {
  double t_s;
  Eigen::Isometry3d estimate;
  Eigen::Isometry3d truth;
  Eigen::Matrix3d covariance;
  double expected_error_m;
};

// The increment a→b's position error, in W (the estimate's frame at a).
Eigen::Vector3d increment_error_w(const RegisteredScan& a, const RegisteredScan& b) {
  const Eigen::Vector3d estimated = (a.estimate.inverse() * b.estimate).translation();
  const Eigen::Vector3d true_motion = (a.truth.inverse() * b.truth).translation();
  return a.estimate.linear() * (estimated - true_motion);
}

double nees_per_dof(const Eigen::Vector3d& error, const Eigen::Matrix3d& covariance) {
  if (!covariance.allFinite()) return kNaN;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(covariance);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || ldlt.vectorD().minCoeff() <= 0.0) return kNaN;
  return error.dot(ldlt.solve(error)) / 3.0;
}

double median(std::vector<double> values) {
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  return quantile_sorted(values, 0.5);
}

double mean(const std::vector<double>& values) {
  if (values.empty()) return kNaN;
  double sum = 0.0;
  for (const double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

// One row of the detector table: a flag rule scored over every run.
struct DetectorRow {
  std::size_t good_scans = 0, good_flagged = 0, good_flagged_slipped = 0, noisy_good_runs = 0, bad_flagged = 0;
  std::size_t slipped = 0, slipped_flagged = 0, others = 0, others_flagged = 0;
  std::vector<std::string> missed;  // runs over the bad-run limit never flagged
};

template <class Flag>
DetectorRow score_detector(const std::vector<RunIntegrity>& runs, const DetectorLimits& limits, Flag&& flagged) {
  DetectorRow row;
  char text[512];
  for (const RunIntegrity& run : runs) {
    std::size_t run_flagged = 0, run_flagged_slipped = 0;
    for (const ScanIntegrity& scan : run.scans) {
      const bool flag = flagged(scan);
      run_flagged += flag ? 1 : 0;
      if (std::isnan(scan.window_error_m)) continue;
      if (scan.window_error_m > limits.slipped_m) {
        ++row.slipped;
        row.slipped_flagged += flag ? 1 : 0;
        run_flagged_slipped += flag ? 1 : 0;
      } else {
        ++row.others;
        row.others_flagged += flag ? 1 : 0;
      }
    }
    if (run.error_cm_per_m < limits.good_run_cm_per_m) {
      row.good_flagged += run_flagged;
      row.good_flagged_slipped += run_flagged_slipped;
      row.good_scans += run.scans.size();
      if (static_cast<double>(run_flagged) > limits.good_run_flag_share * static_cast<double>(run.scans.size()))
        ++row.noisy_good_runs;
    } else if (!(run.error_cm_per_m <= limits.bad_run_cm_per_m)) {
      if (run_flagged > 0) {
        ++row.bad_flagged;
      } else {
        std::snprintf(text, sizeof text, "%s (%.2f cm/m over %.2f m)", run.name.c_str(), run.error_cm_per_m,
                      run.distance_m);
        row.missed.push_back(text);
      }
    }
  }
  return row;
}

std::string percent(std::size_t part, std::size_t whole) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f %%", whole > 0 ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0);
  return text;
}

// "cage-12, 0.620 m over 3.1–9.8 s (40 scans), 2 stretch(es) over"
std::string runaway_over_text(const RunIntegrity& run) {
  char text[512];
  std::snprintf(text, sizeof text, "%s, %s, %zu stretch(es) over", run.name.c_str(),
                largest_growth_text(*run.runaway).c_str(), run.runaway->stretches_over_limit);
  return text;
}

// The bench's runaway: the run whose good stretch grew most, and every run
// over the bar by name, since each of those is a bug to chase.
std::string runaway_table(const std::vector<RunIntegrity>& runs) {
  std::size_t measured = 0;
  const RunIntegrity* largest = nullptr;
  std::vector<std::string> over;
  for (const RunIntegrity& run : runs) {
    if (!run.runaway) continue;
    ++measured;
    if (largest == nullptr || run.runaway->growth_m() > largest->runaway->growth_m()) largest = &run;
    if (run.runaway->growth_m() > kRunawayLimit_m) over.push_back(runaway_over_text(run));
  }
  char text[512];
  std::snprintf(text, sizeof text,
                "\nRunaway: per run, the largest rise of a scan's position error (the estimate aligned at its first "
                "pose) within a stretch of consecutive good scans; none may exceed %.1f m.\n\n"
                "| runs measured (scan log with good_scan) | largest growth | its run | runs over %.1f m |\n"
                "|---|---|---|---|\n| %zu of %zu | %s | %s | %zu |\n",
                kRunawayLimit_m, kRunawayLimit_m, measured, runs.size(),
                largest ? largest_growth_text(*largest->runaway).c_str() : "–", largest ? largest->name.c_str() : "–",
                over.size());
  std::string md = text;
  if (over.empty()) return md;
  std::snprintf(text, sizeof text, "\nRuns over %.1f m:", kRunawayLimit_m);
  md += text;
  for (std::size_t i = 0; i < over.size(); ++i) md += (i == 0 ? " " : "; ") + over[i];
  return md + ".\n";
}

}  // namespace

std::vector<ScanIntegrity> score_scans(const PoseSeries& ground_truth, const PoseSeries& estimate, const ScanLog& log,
                                       std::size_t window) {
  const auto& t_s = log.column("t_s");
  const auto& registered = log.column("registered");
  const auto& iterations = log.column("iterations");
  const auto& expected = log.column("expected_error_m");
  const auto& xx = log.column("cov_txx");
  const auto& yy = log.column("cov_tyy");
  const auto& zz = log.column("cov_tzz");
  const auto& xy = log.column("cov_txy");
  const auto& xz = log.column("cov_txz");
  const auto& yz = log.column("cov_tyz");
  const std::vector<double>* good = log.has_column("good_scan") ? &log.column("good_scan") : nullptr;
  std::vector<RegisteredScan> history;  // the registered scans so far (none after an unregistered one)
  std::vector<ScanIntegrity> out;
  for (std::size_t i = 0; i < log.scans(); ++i) {
    const std::optional<TimedPose> pose = sample_at(estimate, t_s[i]);
    const bool inside = !ground_truth.empty() && t_s[i] >= ground_truth.front().t_s && t_s[i] <= ground_truth.back().t_s;
    if (registered[i] == 0.0 || !pose || !inside) {
      history.clear();
      continue;
    }
    RegisteredScan scan{t_s[i], to_isometry(*pose), pose_at(ground_truth, t_s[i]), Eigen::Matrix3d::Zero(),
                        expected[i]};
    scan.covariance << xx[i], xy[i], xz[i], xy[i], yy[i], yz[i], xz[i], yz[i], zz[i];
    const bool map_start = iterations[i] == 0.0;
    const std::optional<bool> good_scan =
        good ? std::optional<bool>((*good)[i] != 0.0) : std::nullopt;
    if (!map_start && !history.empty()) {
      const RegisteredScan& previous = history.back();
      ScanIntegrity s;
      s.expected_error_m = scan.expected_error_m;
      const Eigen::Vector3d error = increment_error_w(previous, scan);
      s.increment_error_m = error.norm();
      s.window_error_m = history.size() >= window ? increment_error_w(history[history.size() - window], scan).norm() : kNaN;
      s.nees_per_dof = nees_per_dof(error, previous.covariance + scan.covariance);
      s.good_scan = good_scan;
      out.push_back(s);
    }
    if (map_start) history.clear();
    history.push_back(scan);
  }
  return out;
}

std::string integrity_markdown(const std::vector<RunIntegrity>& runs, const std::vector<double>& thresholds_m,
                               const DetectorLimits& limits) {
  std::size_t good_runs = 0, bad_runs = 0;
  for (const RunIntegrity& run : runs) {
    good_runs += run.error_cm_per_m < limits.good_run_cm_per_m ? 1 : 0;
    bad_runs += !(run.error_cm_per_m <= limits.bad_run_cm_per_m) ? 1 : 0;
  }
  char text[512];
  std::snprintf(text, sizeof text,
                "%zu runs: %zu under %.2g cm/m, %zu over %.2g cm/m (or diverged). A scan is flagged when its "
                "expected error is above the threshold; it slipped when its pose's error over the last scans' window "
                "is over %.2g m.\n\n",
                runs.size(), good_runs, limits.good_run_cm_per_m, bad_runs, limits.bad_run_cm_per_m, limits.slipped_m);
  std::string md = text;
  std::snprintf(text, sizeof text,
                "| threshold | scans flagged, runs under %.2g cm/m (of them slipped) | of those runs, over %.0f %% "
                "flagged | runs over %.2g cm/m flagged | slipped scans flagged | other scans flagged |\n"
                "|---|---|---|---|---|---|\n",
                limits.good_run_cm_per_m, limits.good_run_flag_share * 100.0, limits.bad_run_cm_per_m);
  md += text;
  const auto add_row = [&](const std::string& label, const DetectorRow& row) {
    std::snprintf(text, sizeof text, "| %s | %s (%zu of %zu; %zu) | %zu of %zu | %zu of %zu | %s | %s |\n",
                  label.c_str(), percent(row.good_flagged, row.good_scans).c_str(), row.good_flagged, row.good_scans,
                  row.good_flagged_slipped, row.noisy_good_runs, good_runs, row.bad_flagged, bad_runs,
                  percent(row.slipped_flagged, row.slipped).c_str(), percent(row.others_flagged, row.others).c_str());
    md += text;
  };
  const auto add_missed = [&](const std::string& label, const DetectorRow& row) {
    if (row.missed.empty()) return;
    std::snprintf(text, sizeof text, "\nRuns over %.3g cm/m never flagged %s:", limits.bad_run_cm_per_m, label.c_str());
    md += text;
    for (std::size_t i = 0; i < row.missed.size(); ++i) md += (i == 0 ? " " : "; ") + row.missed[i];
    md += ".\n";
  };
  DetectorRow first;
  for (std::size_t k = 0; k < thresholds_m.size(); ++k) {
    const double threshold = thresholds_m[k];
    const DetectorRow row = score_detector(
        runs, limits, [&](const ScanIntegrity& scan) { return !(scan.expected_error_m <= threshold); });
    std::snprintf(text, sizeof text, "%.3g m", threshold);
    add_row(text, row);
    if (k == 0) first = row;
  }
  bool every_scan_judged = true;
  for (const RunIntegrity& run : runs)
    for (const ScanIntegrity& scan : run.scans) every_scan_judged = every_scan_judged && scan.good_scan.has_value();
  std::optional<DetectorRow> verdict;
  if (every_scan_judged) {
    verdict = score_detector(runs, limits, [](const ScanIntegrity& scan) { return !*scan.good_scan; });
    add_row("tumbled's verdict", *verdict);
  }
  if (!thresholds_m.empty()) {
    std::snprintf(text, sizeof text, "at %.3g m", thresholds_m.front());
    add_missed(text, first);
  }
  if (verdict) add_missed("by tumbled's verdict", *verdict);
  if (verdict) {
    md += "\nThe verdict row flags a scan wherever tumbled judged it not good (the scan log's good_scan: the "
          "expected error over daemon.health.max_expected_error_m of the run's config, the gyro clipped about the "
          "spin axis at a spin's start or with little of the map matched, a direction unobserved, a poor "
          "registration), which degrades it from tracking; scored on the same registered scans as the "
          "thresholds.\n";
  } else {
    md += "\nNo verdict row: some scan logs have no good_scan column (written by a tumbled before it).\n";
  }
  md += "\nNEES per degree of freedom of the published position covariance, against each one-scan increment's "
        "error (consistent: mean near 1):\n\n| runs | scans | mean | median |\n|---|---|---|---|\n";
  for (const double limit : {limits.good_run_cm_per_m, limits.bad_run_cm_per_m}) {
    std::vector<double> nees;
    for (const RunIntegrity& run : runs) {
      if (!(run.error_cm_per_m < limit)) continue;
      for (const ScanIntegrity& scan : run.scans)
        if (std::isfinite(scan.nees_per_dof)) nees.push_back(scan.nees_per_dof);
    }
    std::snprintf(text, sizeof text, "| under %.2g cm/m | %zu | %.2f | %.2f |\n", limit, nees.size(), mean(nees),
                  median(nees));
    md += text;
  }
  return md + runaway_table(runs);
}

}  // namespace tumble::eval
