// Reading normals from the scan's own structure instead of a k-nearest
// search (OdometryParams::reading_normal_source): a point's neighbourhood is
// the points next to it in time on its own lidar ring and on the ring just
// above and below it in elevation, each within NormalParams::max_radius_m: a
// window of the range image. When that is one line (the next rings out of
// reach), the window widens ring by ring up to rings_each_side. On a 16-ring
// lidar most k-nearest fits find one ring only and are redone with a 1 m
// search to reach the next; the window has the next rings by construction
// and needs no search. The fit and its validity tests are NormalEstimator's
// (CovarianceAccumulator, NormalParams).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/normals.hpp"
#include "core/parallel_runner.hpp"
#include "core/point_cloud.hpp"
#include "core/types.hpp"

namespace tumble {

// Where the reading's normals come from: the k nearest points (NormalEstimator)
// or a window of the scan's rings (ScanLineNormals).
enum class ReadingNormalSource { kNearest, kScanLines };

struct ScanLineWindow {
  int points_each_side = 5;  // on each ring: this many points before and after in time
  int rings_each_side = 2;   // rings above and below in elevation, at most
};

// The elevation of each laser (index = LidarPoint::laser) in the lidar frame,
// from the first return of that laser in the raw scan; lasers without a
// return get +inf (after every other ring). Resized to the highest laser + 1.
void ring_elevations_rad(const Scan& scan, std::vector<double>& elevations);

class ScanLineNormals {
 public:
  static constexpr int kMaxRingsEachSide = 8;  // ScanLineWindow::rings_each_side, at most

  // Throws std::invalid_argument for a window under 1 point, or under 1 or
  // over kMaxRingsEachSide rings.
  ScanLineNormals(const NormalParams& params, const ScanLineWindow& window, ParallelRunner& runner = serial_runner());

  // Orders the cloud's points by ring elevation (ring_elevation_rad[ring])
  // and, within a ring, by time. The cloud's points, times and rings must
  // not change until the fits are done.
  void index(const PointCloud& cloud, std::span<const double> ring_elevation_rad);
  // Fills normals, curvatures and normal_valid of the listed points.
  void estimate(PointCloud& cloud, const Eigen::Vector3d& viewpoint, std::span<const std::uint32_t> indices) const;

 private:
  static constexpr std::size_t kRings = 256;  // every LidarPoint::laser value
  using RankIterator = std::vector<std::uint32_t>::const_iterator;
  struct RingStretch {  // a ring's part of a window, in by_rank_
    RankIterator begin;
    RankIterator end;
  };
  PlaneFit fit_point(const PointCloud& cloud, const Eigen::Vector3d& viewpoint, std::uint32_t i) const;

  NormalParams params_;
  ScanLineWindow window_;
  ParallelRunner* runner_;
  std::array<std::uint16_t, kRings> rank_of_ring_{};   // elevation rank of each ring
  std::array<std::uint32_t, kRings + 1> rank_begin_{};  // where each rank's points start in by_rank_
  std::vector<std::uint32_t> by_rank_;   // point indices by elevation rank, then time
  std::vector<std::uint32_t> position_;  // per point: its place in by_rank_
};

}  // namespace tumble
