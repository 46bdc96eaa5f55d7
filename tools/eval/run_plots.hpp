// `tumble-eval score --plots DIR`: one run drawn beside its tables, with
// gnuplot — the trajectory against ground truth from above (x, y) and from
// the side (x, z), and the position error over time. The estimate is aligned
// to ground truth at its first pose, as the drift is measured (drift.hpp).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "tools/eval/pose_series.hpp"

namespace tumble::eval {

struct AlignedSample {
  double t_s = 0.0;
  Eigen::Vector3d truth_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d estimate_m = Eigen::Vector3d::Zero();  // aligned at the first pose
  double error_m = 0.0;
};

// Every estimated pose inside the ground truth's time span, aligned; empty
// when none is.
std::vector<AlignedSample> align_at_first_pose(const PoseSeries& ground_truth, const PoseSeries& estimate);

// Writes DIR/run.dat and DIR/{trajectory_top,trajectory_side,error}.png (each
// with its .gp script). Returns "" or why the plots could not be drawn.
std::string draw_run_plots(const PoseSeries& ground_truth, const PoseSeries& estimate,
                           const std::filesystem::path& dir);

}  // namespace tumble::eval
