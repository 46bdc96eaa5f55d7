#include "tools/calib/scan_residual.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace tumble::calib {
namespace {

struct MomentAccumulator {
  double sum = 0;
  double sum_sq = 0;
  std::size_t count = 0;
  void add(double v) {
    sum += v;
    sum_sq += v * v;
    ++count;
  }
  double mean() const {
    return count > 0 ? sum / static_cast<double>(count) : std::numeric_limits<double>::quiet_NaN();
  }
  double rms() const {
    return count > 0 ? std::sqrt(sum_sq / static_cast<double>(count)) : std::numeric_limits<double>::quiet_NaN();
  }
};

}  // namespace

ScanResidual measure_scan_residual(const Scan& scan, std::span<const Eigen::Vector3d> deskewed_l,
                                   const GroundTruth& truth, Rig rig, const Eigen::Vector3d& motion_w,
                                   const ReferenceMap& map, const ResidualParams& params) {
  if (deskewed_l.size() != scan.points.size())
    throw std::invalid_argument("measure_scan_residual: de-skewed points and scan differ in size");
  if (rig == Rig::Other) throw std::invalid_argument("measure_scan_residual: only rail and turntable runs");
  ScanResidual out;
  if (scan.points.empty()) return out;
  const std::size_t stride = params.point_stride > 0 ? params.point_stride : 1;

  std::size_t hint = 0;
  const Eigen::Isometry3d T_w1 = truth.pose_at(scan.points.front().t_s, hint);
  MomentAccumulator residual, deskew_error, range;
  for (std::size_t i = 0; i < scan.points.size(); i += stride) {
    const LidarPoint& point = scan.points[i];
    const Eigen::Vector3d p_l(point.x_m, point.y_m, point.z_m);
    range.add(p_l.norm());
    const Eigen::Vector3d q_odometry = T_w1 * deskewed_l[i];
    const Eigen::Vector3d q_truth = truth.pose_at(point.t_s, hint) * p_l;
    const Eigen::Vector3d error = q_odometry - q_truth;
    const std::optional<MapMatch> match = map.nearest(q_odometry, params.max_match_distance_m);
    if (rig == Rig::Rail) {
      // Both statistics over the same points: those matched to a surface
      // perpendicular to the motion, projected on its normal.
      if (!match) continue;
      const std::optional<Eigen::Vector3d> n = map.normal(match->index);
      if (!n || std::abs(n->dot(motion_w)) < params.perpendicular_min_cos) continue;
      residual.add(std::abs((q_odometry - map.centroid(match->index)).dot(*n)));
      deskew_error.add(std::abs(error.dot(*n)));
    } else {
      if (match) residual.add(match->distance_m);
      deskew_error.add(error.norm());
    }
  }
  out.residual_m = residual.mean();
  out.residual_rms_m = residual.rms();
  out.residual_points = residual.count;
  out.deskew_error_m = deskew_error.mean();
  out.deskew_error_points = deskew_error.count;
  out.mean_range_m = range.mean();
  return out;
}

}  // namespace tumble::calib
