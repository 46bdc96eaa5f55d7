// Scene primitives: each is a canonical shape in its own local frame placed by
// a rigid pose, so every ray test is one transform plus a closed-form solve.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <string>

namespace tumble::sim {

enum class Shape {
  Plane,      // infinite plane z = 0 of the local frame
  Rectangle,  // finite part |x| <= half_size.x, |y| <= half_size.y of z = 0
  Box,        // |x|,|y|,|z| <= half_size; hit from outside or from inside (rooms)
  Cylinder,   // axis = local z, |z| <= half_size.z, radius; optional end caps
};

// How a surface returns a lidar beam. Diffuse: everywhere, by reflectivity;
// specular (polished metal, a mirror): only near normal incidence, the rest
// goes away from the sensor; glass: the beam goes through to what is behind.
enum class Material { Diffuse, Specular, Glass };

struct Primitive {
  Shape shape = Shape::Plane;
  Eigen::Isometry3d pose_w = Eigen::Isometry3d::Identity();  // local -> world
  Eigen::Vector3d half_size = Eigen::Vector3d::Zero();        // x, y used by Rectangle/Box; z by Box/Cylinder
  double radius_m = 0;                                        // Cylinder only
  bool capped = true;                                         // Cylinder only
  double reflectivity = 0.5;                                  // 0..1 (lidar models map to 0..255)
  Material material = Material::Diffuse;
  std::string name;                                           // for messages and debugging only
};

struct Aabb {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  void extend(const Eigen::Vector3d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void extend(const Aabb& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  Eigen::Vector3d center() const { return 0.5 * (min + max); }
};

bool is_bounded(const Primitive& p);    // false for infinite planes
Aabb world_bounds(const Primitive& p);  // exact world-frame box; precondition: is_bounded(p)

}  // namespace tumble::sim
