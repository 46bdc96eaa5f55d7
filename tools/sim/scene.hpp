// A static world of primitives and the nearest-hit query the lidar model uses.
#pragma once

#include "tools/sim/primitives.hpp"
#include "tools/sim/ray_cast.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace tumble::sim {

struct Hit {
  double range_m;           // distance from the origin along the unit direction
  double reflectivity;      // 0..1 of the surface hit
  Eigen::Vector3d normal_w; // unit, facing the ray (dot(normal_w, dir) <= 0)
  Material material = Material::Diffuse;
};

class Scene {
 public:
  Scene() = default;
  explicit Scene(std::vector<Primitive> primitives, std::string name = {});

  // Nearest surface within (0, max_range_m]; nullopt when nothing is hit.
  std::optional<Hit> cast(const Eigen::Vector3d& origin_w, const Eigen::Vector3d& dir_unit_w,
                          double max_range_m) const;

  const std::vector<Primitive>& primitives() const { return primitives_; }
  const std::string& name() const { return name_; }

 private:
  // Flattened bounding-volume hierarchy over the bounded primitives; infinite
  // planes are few and are tested for every ray.
  struct Node {
    Aabb box;
    int first = 0;  // leaf: first index into bounded_; inner: index of the right child (the left follows the node)
    int count = 0;  // leaf: number of primitives; 0 for an inner node
  };
  int build(int begin, int end);

  std::vector<Primitive> primitives_;
  std::vector<int> bounded_;    // indices of bounded primitives, in BVH leaf order
  std::vector<int> unbounded_;  // indices of infinite planes
  std::vector<Node> nodes_;
  std::string name_;
};

}  // namespace tumble::sim
