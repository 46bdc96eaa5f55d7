// Exact analytic ray/primitive intersection. A ray is origin + t * dir with a
// unit dir; t is then the range in metres. Surfaces are two-sided: the normal
// returned always faces the ray (dot(normal, dir) <= 0).
#pragma once

#include "tools/sim/primitives.hpp"

#include <Eigen/Core>

#include <optional>

namespace tumble::sim {

struct Ray {
  Eigen::Vector3d origin_w;
  Eigen::Vector3d dir_unit_w;
};

struct PrimitiveHit {
  double t_m = 0;
  Eigen::Vector3d normal_w = Eigen::Vector3d::Zero();
};

// Hits closer than kMinHitRange_m are ignored so that a ray starting on a
// surface does not hit that surface again.
inline constexpr double kMinHitRange_m = 1e-9;

// The nearest hit with kMinHitRange_m < t < t_max_m, if any.
std::optional<PrimitiveHit> intersect(const Primitive& prim, const Ray& ray, double t_max_m);

// Ray vs axis-aligned box with precomputed 1/dir: entry distance if the ray
// overlaps the box within [0, t_max_m], otherwise +infinity.
double ray_aabb_entry(const Aabb& box, const Eigen::Vector3d& origin, const Eigen::Vector3d& inv_dir, double t_max_m);

}  // namespace tumble::sim
