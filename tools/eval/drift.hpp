// Drift of an estimated trajectory against ground truth, as in the paper
// (§V-B): the final pose error divided by the distance travelled, plus the
// relative pose error (RPE) over segments of fixed travelled distance.
//
// The estimate lives in its own frame (tumbled: the lidar at initialisation,
// levelled); it is aligned to ground truth at its first pose, i.e. both are
// compared as motions from that instant, which is what the paper measures
// (the transformation between the initial and final poses of a run).
// Ground truth is interpolated at the estimate's times.
#pragma once

#include <cstddef>

#include "tools/eval/pose_series.hpp"

namespace tumble::eval {

struct DriftOptions {
  double segment_m = 1.0;  // RPE segment length, in ground-truth distance travelled
};

struct DriftResult {
  std::size_t poses = 0;  // estimated poses inside the ground truth's time span (the ones used)
  double first_t_s = 0.0;
  double last_t_s = 0.0;
  double distance_m = 0.0;  // along ground truth, first to last used pose
  double final_translation_error_m = 0.0;
  double final_rotation_error_deg = 0.0;
  double translation_cm_per_m = 0.0;  // final translation error / distance
  double rotation_deg_per_m = 0.0;    // final rotation error / distance
  // RPE: from every used pose to the first later pose at least segment_m of
  // ground-truth travel away; each segment's error divided by its travelled
  // distance, then averaged. NaN when the run is shorter than one segment.
  std::size_t rpe_segments = 0;
  double rpe_translation_cm_per_m = 0.0;
  double rpe_rotation_deg_per_m = 0.0;
};

// Error of the estimated motion a→b against the true motion a→b:
// E = (G_a⁻¹ G_b)⁻¹ (A_a⁻¹ A_b). Its translation norm equals the position
// error at b after aligning A to G at a.
Eigen::Isometry3d relative_motion_error(const Eigen::Isometry3d& truth_a, const Eigen::Isometry3d& truth_b,
                                        const Eigen::Isometry3d& estimate_a, const Eigen::Isometry3d& estimate_b);

// Throws std::invalid_argument when fewer than two estimated poses fall inside
// the ground truth, or the ground truth does not move between them.
DriftResult evaluate_drift(const PoseSeries& ground_truth, const PoseSeries& estimate, const DriftOptions& options);

}  // namespace tumble::eval
