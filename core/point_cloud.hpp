// The plain point data the registration works on: one scan after de-skewing,
// down-sampling and weighting, or any subset of it.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tumble {

// One point with what the weighted point-to-plane cost needs to know about it
// (docs/method.md §3): sigma_n_m is the sensor noise, sigma_s_m the skew
// uncertainty of the weight model, weight the SAW weight (1 for other models).
struct WeightedPoint {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  double t_s = 0;
  double sigma_n_m = 0.02;
  double sigma_s_m = 0;
  double weight = 1;
};

// Struct-of-arrays cloud: the per-stage loops touch one or two attributes at a
// time (positions for the neighbour search, sigmas for the weights), so each
// attribute is contiguous. All arrays have size() elements; resize() and clear()
// keep the capacity, so a cloud reused scan after scan stops allocating.
struct PointCloud {
  std::vector<Eigen::Vector3d> points;   // m, in the cloud's frame
  std::vector<double> times_s;           // acquisition time of each point
  std::vector<std::uint8_t> rings;       // laser index (LidarPoint::laser)
  std::vector<Eigen::Vector3d> normals;  // unit; toward the sensor; see normal_valid
  std::vector<double> curvatures;        // smallest PCA eigenvalue / sum of the three
  std::vector<std::uint8_t> normal_valid;  // 0 where the neighbourhood had no plane
  std::vector<double> sigma_n_m;
  std::vector<double> sigma_s_m;
  std::vector<double> weights;

  std::size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }

  void resize(std::size_t n) {
    points.resize(n, Eigen::Vector3d::Zero());
    times_s.resize(n, 0.0);
    rings.resize(n, 0);
    normals.resize(n, Eigen::Vector3d::Zero());
    curvatures.resize(n, 0.0);
    normal_valid.resize(n, 0);
    sigma_n_m.resize(n, 0.02);
    sigma_s_m.resize(n, 0.0);
    weights.resize(n, 1.0);
  }
  void clear() { resize(0); }
  void reserve(std::size_t n) {
    points.reserve(n);
    times_s.reserve(n);
    rings.reserve(n);
    normals.reserve(n);
    curvatures.reserve(n);
    normal_valid.reserve(n);
    sigma_n_m.reserve(n);
    sigma_s_m.reserve(n);
    weights.reserve(n);
  }

  // Copies every attribute of point i of `from` into slot j of this cloud.
  void copy_point(std::size_t j, const PointCloud& from, std::size_t i) {
    points[j] = from.points[i];
    times_s[j] = from.times_s[i];
    rings[j] = from.rings[i];
    normals[j] = from.normals[i];
    curvatures[j] = from.curvatures[i];
    normal_valid[j] = from.normal_valid[i];
    sigma_n_m[j] = from.sigma_n_m[i];
    sigma_s_m[j] = from.sigma_s_m[i];
    weights[j] = from.weights[i];
  }

  WeightedPoint weighted_point(std::size_t i) const {
    return WeightedPoint{points[i], times_s[i], sigma_n_m[i], sigma_s_m[i], weights[i]};
  }
};

}  // namespace tumble
