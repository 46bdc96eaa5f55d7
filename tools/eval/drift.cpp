#include "tools/eval/drift.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace tumble::eval {

Eigen::Isometry3d relative_motion_error(const Eigen::Isometry3d& truth_a, const Eigen::Isometry3d& truth_b,
                                        const Eigen::Isometry3d& estimate_a, const Eigen::Isometry3d& estimate_b) {
  return (truth_a.inverse() * truth_b).inverse() * (estimate_a.inverse() * estimate_b);
}

DriftResult evaluate_drift(const PoseSeries& ground_truth, const PoseSeries& estimate, const DriftOptions& options) {
  if (ground_truth.size() < 2) throw std::invalid_argument("ground truth has fewer than 2 poses");
  if (!(options.segment_m > 0.0)) throw std::invalid_argument("RPE segment length must be positive");

  // Estimated poses inside the ground truth, with the true pose at the same time
  // and the distance travelled since the first of them.
  std::vector<Eigen::Isometry3d> truth;
  std::vector<Eigen::Isometry3d> estimated;
  std::vector<double> travelled_m;
  std::vector<double> times_s;
  for (const TimedPose& pose : estimate) {
    if (pose.t_s < ground_truth.front().t_s || pose.t_s > ground_truth.back().t_s) continue;
    travelled_m.push_back(times_s.empty() ? 0.0
                                          : travelled_m.back() + path_length_m(ground_truth, times_s.back(), pose.t_s));
    times_s.push_back(pose.t_s);
    truth.push_back(pose_at(ground_truth, pose.t_s));
    estimated.push_back(to_isometry(pose));
  }
  if (times_s.size() < 2)
    throw std::invalid_argument(std::to_string(times_s.size()) +
                                " estimated pose(s) inside the ground truth's time span (need 2)");

  DriftResult result;
  result.poses = times_s.size();
  result.first_t_s = times_s.front();
  result.last_t_s = times_s.back();
  result.distance_m = travelled_m.back();
  if (!(result.distance_m > 0.0))
    throw std::invalid_argument("the ground truth does not move between the first and last estimated poses");

  const Eigen::Isometry3d final_error =
      relative_motion_error(truth.front(), truth.back(), estimated.front(), estimated.back());
  result.final_translation_error_m = final_error.translation().norm();
  result.final_rotation_error_deg = rotation_angle_deg(final_error.linear());
  result.translation_cm_per_m = 100.0 * result.final_translation_error_m / result.distance_m;
  result.rotation_deg_per_m = result.final_rotation_error_deg / result.distance_m;

  double translation_sum = 0.0;
  double rotation_sum = 0.0;
  std::size_t end = 1;
  for (std::size_t start = 0; start < times_s.size(); ++start) {
    end = std::max(end, start + 1);
    while (end < times_s.size() && travelled_m[end] - travelled_m[start] < options.segment_m) ++end;
    if (end == times_s.size()) break;
    const double segment_m = travelled_m[end] - travelled_m[start];
    const Eigen::Isometry3d error = relative_motion_error(truth[start], truth[end], estimated[start], estimated[end]);
    translation_sum += 100.0 * error.translation().norm() / segment_m;
    rotation_sum += rotation_angle_deg(error.linear()) / segment_m;
    ++result.rpe_segments;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  result.rpe_translation_cm_per_m = result.rpe_segments > 0 ? translation_sum / result.rpe_segments : nan;
  result.rpe_rotation_deg_per_m = result.rpe_segments > 0 ? rotation_sum / result.rpe_segments : nan;
  return result;
}

}  // namespace tumble::eval
