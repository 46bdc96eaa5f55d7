// One scan's residuals (paper §V-A): the scan de-skewed with the odometry's
// trajectory, placed at its exact (ground-truth) pose at its first point, and
// compared with the reference map.
//
// Placing it at the true pose, not registering it, is deliberate: the paper's
// conversions r_v ≈ σ_v τ/2 and r_ω ≈ σ_ω τ d/2 assume the error grows from
// zero at the first point (where the pose is right) to σ·τ at the last; a
// registration would centre the error and halve it.
//
// Two numbers per scan:
//  - residual_m, what the paper measures (noise included): for the rail,
//    the mean |e·n| over points whose map surface is perpendicular to the
//    motion (the only ones a linear de-skew error moves off their surface);
//    for the turntable, the mean Euclidean distance to the nearest map point
//    over all points (the paper's choice: it grows more than |e·n| under a
//    rotation error).
//  - deskew_error_m, what the simulator alone can give, and what the fitted
//    model is meant to predict: the same statistic of the noise-free de-skew
//    error d_i = (point de-skewed with the odometry) − (point de-skewed with
//    the ground truth), both in the world frame: mean |d_i·n| over the same
//    points and normals as residual_m (rail), mean |d_i| over all points
//    (turntable).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <span>

#include "core/types.hpp"
#include "tools/calib/bench_index.hpp"
#include "tools/calib/ground_truth.hpp"
#include "tools/calib/reference_map.hpp"

namespace tumble::calib {

struct ResidualParams {
  double max_match_distance_m = 0.5;     // farther points have no counterpart in the map: not counted
  double perpendicular_min_cos = 0.866;  // |n·motion| ≥ cos 30°: a surface "perpendicular to the motion"
  std::size_t point_stride = 1;          // every n-th point (1: all)
};

struct ScanResidual {
  double residual_m = 0;  // NaN when no point qualified
  double residual_rms_m = 0;
  std::size_t residual_points = 0;
  double deskew_error_m = 0;  // NaN when no point qualified
  std::size_t deskew_error_points = 0;
  double mean_range_m = 0;  // d of r_ω ≈ σ_ω τ d / 2: mean range of the scan's points
};

// deskewed_l[i]: scan.points[i] de-skewed with the odometry's trajectory (lidar
// frame at the first point). motion_w: unit direction of the rail's travel in
// the world frame (used by the rail only).
ScanResidual measure_scan_residual(const Scan& scan, std::span<const Eigen::Vector3d> deskewed_l,
                                   const GroundTruth& truth, Rig rig, const Eigen::Vector3d& motion_w,
                                   const ReferenceMap& map, const ResidualParams& params);

}  // namespace tumble::calib
