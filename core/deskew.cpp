// See deskew.hpp.
#include "core/deskew.hpp"

#include <stdexcept>
#include <string>

namespace tumble {

namespace {

void require_same_size(std::size_t points, std::size_t other, const char* what) {
  if (points != other) {
    throw std::invalid_argument(std::string("deskew: ") + what + " has " + std::to_string(other) +
                                " entries for " + std::to_string(points) + " points");
  }
}

}  // namespace

void deskew_points(std::span<const Eigen::Vector3d> points_l, std::span<const double> times_s, double t_ref_s,
                   const Trajectory& trajectory, std::span<Eigen::Vector3d> out_points) {
  require_same_size(points_l.size(), times_s.size(), "times_s");
  require_same_size(points_l.size(), out_points.size(), "out_points");
  RelativePoseInterpolator interpolator(trajectory, t_ref_s);
  for (std::size_t i = 0; i < points_l.size(); ++i) {
    out_points[i] = interpolator.point_to_reference(times_s[i], points_l[i]);
  }
}

void deskew_scan(const Scan& scan, const Trajectory& trajectory, bool enabled, std::span<Eigen::Vector3d> out_points) {
  require_same_size(scan.points.size(), out_points.size(), "out_points");
  auto measured = [&](std::size_t i) {
    const LidarPoint& point = scan.points[i];
    return Eigen::Vector3d(point.x_m, point.y_m, point.z_m);
  };
  if (!enabled || scan.points.empty()) {
    for (std::size_t i = 0; i < scan.points.size(); ++i) out_points[i] = measured(i);
    return;
  }
  RelativePoseInterpolator interpolator(trajectory, scan.points.front().t_s);
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    out_points[i] = interpolator.point_to_reference(scan.points[i].t_s, measured(i));
  }
}

}  // namespace tumble
