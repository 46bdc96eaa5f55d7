#include "tools/sim/ray_cast.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tumble::sim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Candidate bookkeeping in the local frame: keep the nearest admissible t.
struct Nearest {
  double t_max;
  double t = kInf;
  Eigen::Vector3d normal_l = Eigen::Vector3d::Zero();
  void offer(double t_candidate, const Eigen::Vector3d& n) {
    if (t_candidate > kMinHitRange_m && t_candidate <= t_max && t_candidate < t) {
      t = t_candidate;
      normal_l = n;
    }
  }
};

void plane_z0(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& half, bool finite,
              Nearest& best) {
  if (d.z() == 0.0) return;  // parallel: a grazing ray sees no area
  const double t = -o.z() / d.z();
  if (finite) {
    const Eigen::Vector3d p = o + t * d;
    if (std::abs(p.x()) > half.x() || std::abs(p.y()) > half.y()) return;
  }
  best.offer(t, Eigen::Vector3d::UnitZ());
}

void box(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& half, Nearest& best) {
  double t_near = -kInf, t_far = kInf;
  int axis_near = -1, axis_far = -1;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (std::abs(o[i]) > half[i]) return;
      continue;
    }
    double t1 = (-half[i] - o[i]) / d[i];
    double t2 = (half[i] - o[i]) / d[i];
    if (t1 > t2) std::swap(t1, t2);
    if (t1 > t_near) {
      t_near = t1;
      axis_near = i;
    }
    if (t2 < t_far) {
      t_far = t2;
      axis_far = i;
    }
  }
  if (t_near > t_far) return;
  // Entering face from outside, else the exit face seen from inside.
  if (axis_near >= 0 && t_near > kMinHitRange_m) {
    best.offer(t_near, Eigen::Vector3d::Unit(axis_near));
  } else if (axis_far >= 0) {
    best.offer(t_far, Eigen::Vector3d::Unit(axis_far));
  }
}

void cylinder(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double r, double half_h, bool capped,
              Nearest& best) {
  const double a = d.x() * d.x() + d.y() * d.y();
  if (a > 0.0) {
    const double b = o.x() * d.x() + o.y() * d.y();
    const double c = o.x() * o.x() + o.y() * o.y() - r * r;
    const double disc = b * b - a * c;
    if (disc >= 0.0) {
      // Numerically stable roots of a t^2 + 2 b t + c = 0.
      const double q = -(b + std::copysign(std::sqrt(disc), b));
      const double roots[2] = {q / a, q != 0.0 ? c / q : q / a};
      for (double t : roots) {
        const Eigen::Vector3d p = o + t * d;
        if (std::abs(p.z()) <= half_h) best.offer(t, Eigen::Vector3d(p.x(), p.y(), 0.0) / r);
      }
    }
  }
  if (capped && d.z() != 0.0) {
    for (double z : {-half_h, half_h}) {
      const double t = (z - o.z()) / d.z();
      const Eigen::Vector3d p = o + t * d;
      if (p.x() * p.x() + p.y() * p.y() <= r * r) best.offer(t, Eigen::Vector3d::UnitZ());
    }
  }
}

}  // namespace

std::optional<PrimitiveHit> intersect(const Primitive& prim, const Ray& ray, double t_max_m) {
  const Eigen::Matrix3d& R = prim.pose_w.linear();
  const Eigen::Vector3d o = R.transpose() * (ray.origin_w - prim.pose_w.translation());
  const Eigen::Vector3d d = R.transpose() * ray.dir_unit_w;
  Nearest best{t_max_m};
  switch (prim.shape) {
    case Shape::Plane: plane_z0(o, d, prim.half_size, false, best); break;
    case Shape::Rectangle: plane_z0(o, d, prim.half_size, true, best); break;
    case Shape::Box: box(o, d, prim.half_size, best); break;
    case Shape::Cylinder: cylinder(o, d, prim.radius_m, prim.half_size.z(), prim.capped, best); break;
  }
  if (best.t == kInf) return std::nullopt;
  // Two-sided surfaces: report the side facing the ray.
  const Eigen::Vector3d n = best.normal_l.dot(d) > 0 ? -best.normal_l : best.normal_l;
  return PrimitiveHit{best.t, R * n};
}

double ray_aabb_entry(const Aabb& b, const Eigen::Vector3d& origin, const Eigen::Vector3d& inv_dir, double t_max_m) {
  double t_lo = 0.0, t_hi = t_max_m;
  for (int i = 0; i < 3; ++i) {
    if (std::isinf(inv_dir[i])) {  // parallel to this slab: inside it or never
      if (origin[i] < b.min[i] || origin[i] > b.max[i]) return kInf;
      continue;
    }
    const double t1 = (b.min[i] - origin[i]) * inv_dir[i];
    const double t2 = (b.max[i] - origin[i]) * inv_dir[i];
    t_lo = std::max(t_lo, std::min(t1, t2));
    t_hi = std::min(t_hi, std::max(t1, t2));
  }
  return t_lo <= t_hi ? t_lo : kInf;
}

}  // namespace tumble::sim
