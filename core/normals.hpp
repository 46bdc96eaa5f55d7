// Surface normals and curvature by PCA over a point's k nearest neighbours
// (docs/method.md §4: k ≈ 15 for the reading, ≈ 20 for the map; GVTW needs the
// normal, SAW the curvature, point-to-plane ICP the map's normals).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "core/grid_search.hpp"
#include "core/parallel_runner.hpp"
#include "core/point_cloud.hpp"
#include "core/point_grid.hpp"

namespace tumble {

struct NormalParams {
  int k = 15;                  // neighbours, the point itself included
  double max_radius_m = 1.0;   // neighbours farther away are not used
  // Cell of the search grid (speed only, not the result). Sparse 16-ring
  // scans send many searches to max_radius_m (line retries): at 0.5 m they
  // visit 125 cells, at 0.25 m 729 (simulated garage run: half the time).
  double grid_cell_m = 0.5;
  // Smallest middle/largest eigenvalue ratio for a plane: below it the
  // neighbourhood is a line (one lidar ring) and its "normal" is arbitrary.
  double min_planarity = 0.01;
  // Smallest |cos| between the normal and the line of sight. One lidar ring
  // alone (sparse 16-beam scans: the floor far away, a ring crossing a corner)
  // fits a tangent plane of the ring's cone, which contains the line of sight:
  // such a "plane" is an artefact of the scan pattern, not a surface.
  double min_cos_incidence = 0.087;  // cos 85°
  // Largest curvature (λ0 / Σλ) of a usable fit: above it the neighbourhood
  // straddles an edge and its normal is a blend of two surfaces.
  double max_curvature = 0.1;
  // A line-like neighbourhood is refitted once with this many neighbours (0:
  // never): on a 16-beam lidar the floor's rings are metres apart at range,
  // so k ≈ 20 neighbours lie on one ring; a wider neighbourhood reaches the
  // next ring and sees the surface.
  int line_retry_k = 80;
  // Neighbours needed from scan lines (lidar ring of one scan) other than the
  // query's own. One ring alone lies on the ring's cone: across a corner it
  // fits a plane that is no surface, and grazing tests cannot always tell.
  // 0 disables the test (clouds that are not lidar scans).
  int min_other_line_neighbours = 3;
};

struct PlaneFit {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit
  double curvature = 0;  // smallest eigenvalue / sum of eigenvalues, in [0, 1/3]
  bool valid = false;    // false: fewer than 3 points, a line, an edge, grazing
  bool line_like = false;  // the neighbourhood spans a line, not a surface
};

// Accumulates a neighbourhood's first and second moments relative to an origin
// near the points (the query), which keeps the covariance exact far from (0,0,0).
class CovarianceAccumulator {
 public:
  explicit CovarianceAccumulator(const Eigen::Vector3d& origin) : origin_(origin) {}
  void add(const Eigen::Vector3d& p) {
    const Eigen::Vector3d d = p - origin_;
    sum_ += d;
    sum_outer_.noalias() += d * d.transpose();
    ++count_;
  }
  int count() const { return count_; }

  // The best plane through the points; the normal is flipped to point toward
  // `viewpoint` (the sensor) and is the beam direction when the fit is invalid.
  PlaneFit fit(const Eigen::Vector3d& viewpoint, const NormalParams& limits) const;

 private:
  Eigen::Vector3d origin_;
  Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_outer_ = Eigen::Matrix3d::Zero();
  int count_ = 0;
};

// A fit with fewer than params.min_other_line_neighbours neighbours from
// other scan lines becomes an invalid, line-like fit facing the sensor.
inline void reject_single_line(PlaneFit& fit, int other_lines, const Eigen::Vector3d& query,
                               const Eigen::Vector3d& viewpoint, const NormalParams& params) {
  if (other_lines >= params.min_other_line_neighbours) return;
  fit.valid = false;
  fit.line_like = true;
  const Eigen::Vector3d to_sensor = viewpoint - query;
  if (to_sensor.norm() > 0) fit.normal = to_sensor.normalized();
}

// Writes a fit into point i's normal, curvature and normal_valid.
inline void store_fit(PointCloud& cloud, std::size_t i, const PlaneFit& fit) {
  cloud.normals[i] = fit.normal;
  cloud.curvatures[i] = fit.curvature;
  cloud.normal_valid[i] = fit.valid ? 1 : 0;
}

// Normals for every point of a cloud from its neighbours in the same cloud,
// the points' fits spread over `runner`'s threads.
class NormalEstimator {
 public:
  explicit NormalEstimator(const NormalParams& params = {}, ParallelRunner& runner = serial_runner());

  // The plane through the up to `k` (or line_retry_k) nearest neighbours of
  // query found by knn(query, max_radius, storage, k) -> count (storage holds
  // 2k, for the faster search of large k; the neighbours may come in any
  // order, see KnnOrder), indices resolved by
  // position(index) and line(index) (the scan line of that neighbour; the
  // query's is query_line). Shared by the reading and the map.
  template <class Knn, class Position, class Line>
  static PlaneFit fit_neighbourhood(const Eigen::Vector3d& query, std::uint32_t query_line,
                                    const Eigen::Vector3d& viewpoint, const NormalParams& params,
                                    std::vector<Neighbour>& buffer, Knn&& knn, Position&& position, Line&& line) {
    auto fit_k = [&](int k) {
      buffer.resize(2 * static_cast<std::size_t>(k));
      const std::size_t found = knn(query, params.max_radius_m, std::span<Neighbour>(buffer), static_cast<std::size_t>(k));
      CovarianceAccumulator acc(query);
      int other_lines = 0;
      for (std::size_t j = 0; j < found; ++j) {
        acc.add(position(buffer[j].index));
        if (line(buffer[j].index) != query_line) ++other_lines;
      }
      PlaneFit fit = acc.fit(viewpoint, params);
      reject_single_line(fit, other_lines, query, viewpoint, params);
      return fit;
    };
    PlaneFit fit = fit_k(params.k);
    if (fit.line_like && params.line_retry_k > params.k) fit = fit_k(params.line_retry_k);
    return fit;
  }

  // Fills cloud.normals, curvatures and normal_valid; a point's scan line is
  // its ring (cloud.rings). viewpoint: the sensor position in the cloud's
  // frame. Buffers are kept between calls.
  void estimate(PointCloud& cloud, const Eigen::Vector3d& viewpoint);

  // The same in two steps, for a pipeline that needs the normals of a few
  // points only (each fit from its neighbours in the whole cloud, exactly as
  // estimate() fits it): index the cloud's positions, then fit the points
  // listed. The cloud's positions and rings must not change in between.
  void index(const PointCloud& cloud);
  void estimate(PointCloud& cloud, const Eigen::Vector3d& viewpoint, std::span<const std::uint32_t> indices);

  const NormalParams& params() const { return params_; }

 private:
  void fit_point(PointCloud& cloud, const Eigen::Vector3d& viewpoint, std::size_t i, std::vector<Neighbour>& buffer) const;

  NormalParams params_;
  ParallelRunner* runner_;
  PointGrid grid_;
  std::vector<std::vector<Neighbour>> neighbours_;  // per worker
};

}  // namespace tumble
