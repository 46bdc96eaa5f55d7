#include "tools/eval/runaway.hpp"

#include <algorithm>
#include <cstdio>

#include "tools/eval/drift.hpp"

namespace tumble::eval {
namespace {

// The pose the estimate is aligned at, with ground truth there: the first
// estimated pose inside the ground truth, as evaluate_drift takes it.
struct Alignment {
  double t_s = 0.0;
  Eigen::Isometry3d truth;
  Eigen::Isometry3d estimate;
};

std::optional<Alignment> first_pose(const PoseSeries& ground_truth, const PoseSeries& estimate) {
  if (ground_truth.size() < 2) return std::nullopt;
  for (const TimedPose& pose : estimate)
    if (pose.t_s >= ground_truth.front().t_s && pose.t_s <= ground_truth.back().t_s)
      return Alignment{pose.t_s, pose_at(ground_truth, pose.t_s), to_isometry(pose)};
  return std::nullopt;
}

std::optional<double> position_error_m(const PoseSeries& ground_truth, const PoseSeries& estimate,
                                       const Alignment& first, double t_s) {
  const std::optional<TimedPose> pose = sample_at(estimate, t_s);
  if (!pose || t_s < ground_truth.front().t_s || t_s > ground_truth.back().t_s) return std::nullopt;
  return relative_motion_error(first.truth, pose_at(ground_truth, t_s), first.estimate, to_isometry(*pose))
      .translation()
      .norm();
}

// A good stretch being read: its growth so far needs only the lowest error so far.
struct OpenStretch {
  GoodStretch stretch;
  double lowest_error_m = 0.0;

  OpenStretch(double t_s, double error_m) : stretch{t_s, t_s, 0, 0.0}, lowest_error_m(error_m) {}

  void add(double t_s, double error_m) {
    stretch.end_s = t_s;
    ++stretch.scans;
    lowest_error_m = std::min(lowest_error_m, error_m);
    stretch.growth_m = std::max(stretch.growth_m, error_m - lowest_error_m);
  }
};

void close_stretch(std::optional<OpenStretch>& open, double limit_m, Runaway& runaway) {
  if (!open) return;
  const GoodStretch& stretch = open->stretch;
  if (stretch.growth_m > limit_m) ++runaway.stretches_over_limit;
  if (!runaway.largest || stretch.growth_m > runaway.largest->growth_m) runaway.largest = stretch;
  open.reset();
}

}  // namespace

std::vector<ScanVerdict> scan_verdicts(const PoseSeries& ground_truth, const PoseSeries& estimate, const ScanLog& log) {
  const std::vector<double>& t_s = log.column("t_s");
  const std::vector<double>& registered = log.column("registered");
  const std::vector<double>& good_scan = log.column("good_scan");
  const std::optional<Alignment> first = first_pose(ground_truth, estimate);
  std::vector<ScanVerdict> verdicts(log.scans());
  for (std::size_t i = 0; i < verdicts.size(); ++i) {
    ScanVerdict& verdict = verdicts[i];
    verdict.good = registered[i] != 0.0 && good_scan[i] != 0.0;
    if (!first) continue;
    verdict.t_s = t_s[i] - first->t_s;
    if (registered[i] != 0.0) verdict.position_error_m = position_error_m(ground_truth, estimate, *first, t_s[i]);
  }
  return verdicts;
}

Runaway find_runaway(const std::vector<ScanVerdict>& scans, double limit_m) {
  Runaway runaway;
  runaway.scans = scans.size();
  std::optional<OpenStretch> open;
  for (const ScanVerdict& scan : scans) {
    if (!scan.good) {
      ++runaway.not_good_scans;
      close_stretch(open, limit_m, runaway);
      continue;
    }
    if (!scan.position_error_m) continue;
    if (!open) open.emplace(scan.t_s, *scan.position_error_m);
    open->add(scan.t_s, *scan.position_error_m);
  }
  close_stretch(open, limit_m, runaway);
  return runaway;
}

std::optional<Runaway> runaway_of(const PoseSeries& ground_truth, const PoseSeries& estimate, const ScanLog& log) {
  if (!log.has_column("good_scan")) return std::nullopt;
  return find_runaway(scan_verdicts(ground_truth, estimate, log));
}

std::string largest_growth_text(const Runaway& runaway) {
  if (!runaway.largest) return "0.000 m (no good scan with a pose)";
  const GoodStretch& stretch = *runaway.largest;
  char text[128];
  std::snprintf(text, sizeof text, "%.3f m over %.1f–%.1f s (%zu scans)", stretch.growth_m, stretch.start_s,
                stretch.end_s, stretch.scans);
  return text;
}

}  // namespace tumble::eval
