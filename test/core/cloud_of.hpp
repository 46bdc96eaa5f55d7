// A point cloud of the given points, every one with the same skew σ.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "core/point_cloud.hpp"

namespace tumble::test {

inline PointCloud cloud_of(const std::vector<Eigen::Vector3d>& points, double sigma_s_m = 0) {
  PointCloud c;
  c.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    c.points[i] = points[i];
    c.sigma_s_m[i] = sigma_s_m;
  }
  return c;
}

}  // namespace tumble::test
