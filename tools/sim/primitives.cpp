#include "tools/sim/primitives.hpp"

#include <cmath>

namespace tumble::sim {

bool is_bounded(const Primitive& p) { return p.shape != Shape::Plane; }

Aabb world_bounds(const Primitive& p) {
  Aabb box;
  const Eigen::Matrix3d& R = p.pose_w.linear();
  const Eigen::Vector3d c = p.pose_w.translation();
  if (p.shape == Shape::Cylinder) {
    // Exact: along world axis i the rim reaches r * sqrt(1 - a_i^2) beyond the axis ends.
    const Eigen::Vector3d a = R.col(2);
    const Eigen::Vector3d rim = (Eigen::Vector3d::Ones() - a.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt() * p.radius_m;
    const Eigen::Vector3d half = a.cwiseAbs() * p.half_size.z() + rim;
    box.extend(c - half);
    box.extend(c + half);
    return box;
  }
  const double hz = p.shape == Shape::Box ? p.half_size.z() : 0.0;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d corner((i & 1) ? p.half_size.x() : -p.half_size.x(),
                                 (i & 2) ? p.half_size.y() : -p.half_size.y(), (i & 4) ? hz : -hz);
    box.extend(c + R * corner);
  }
  return box;
}

}  // namespace tumble::sim
