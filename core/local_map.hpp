// The rolling local map (algorithm.md §5): registered points in the world
// frame, in a voxel hash (KISS-ICP / iVox style), bounded in space (radius
// around the current pose) and in density (a minimum point spacing and a cap
// per voxel), with the normals and sigmas the weighted point-to-plane ICP uses.
#pragma once

#include <tsl/robin_map.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

#include "core/grid_search.hpp"
#include "core/normals.hpp"
#include "core/point_cloud.hpp"

namespace tumble {

struct LocalMapParams {
  double voxel_size_m = 0.25;            // hash cell; also the search grid
  std::size_t max_points_per_voxel = 40; // a full voxel takes no more points
  double radius_m = 50;                  // voxels farther from the pose are dropped
  double min_point_distance_m = 0.05;    // no new point this close to a map point
  double max_sigma_s_m = 1.0;            // points less certain than this stay out
  // PCA of the map normals: k = 20 neighbours (the authors' value); see
  // NormalParams for the validity limits.
  NormalParams normals{.k = 20};
};

struct MapPoint {
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_w = Eigen::Vector3d::UnitZ();
  double sigma_n_m = 0.02;
  double sigma_s_m = 0;
  double curvature = 0;
  std::uint32_t line_id = 0;  // scan line: insert() call number << 8 | ring
  bool normal_valid = false;
};

struct MapInsertStats {
  std::size_t inserted = 0;
  std::size_t rejected_sigma = 0;     // sigma_s above max_sigma_s_m
  std::size_t rejected_too_close = 0; // a map point within min_point_distance_m
  std::size_t rejected_voxel_full = 0;
};

class LocalMap {
 public:
  explicit LocalMap(const LocalMapParams& params = {});

  // Inserts the points of `cloud` (frame L, rings used for the scan lines)
  // registered at T_wl, then fits the
  // normals of the new points from the map around them (this scan included),
  // oriented toward the sensor position. Existing points keep their normals:
  // a map point is static once registered, and refitting the neighbourhood of
  // every insertion would cost O(touched voxels x points) per scan.
  MapInsertStats insert(const PointCloud& cloud, const Eigen::Isometry3d& T_wl);

  // Drops every voxel whose centre is farther than radius_m from centre_w.
  std::size_t remove_far_from(const Eigen::Vector3d& centre_w);

  // The up to storage.size() nearest map points of q_w within max_distance_m,
  // nearest first; returns how many. Resolve an index with point().
  std::size_t knn(const Eigen::Vector3d& q_w, double max_distance_m, std::span<Neighbour> storage) const;
  const MapPoint& point(std::uint32_t index) const {
    return voxels_[index / cap_].points[index % cap_];
  }

  std::size_t size() const { return point_count_; }
  std::size_t voxel_count() const { return cell_slot_.size(); }
  bool empty() const { return point_count_ == 0; }
  void clear();
  const LocalMapParams& params() const { return params_; }

  template <class F>
  void for_each_point(F&& f) const {
    for (const auto& [key, slot] : cell_slot_)
      for (const MapPoint& p : voxels_[slot].points) f(p);
  }

 private:
  struct Voxel {
    CellKey key;
    std::vector<MapPoint> points;  // capacity max_points_per_voxel, kept when recycled
  };
  bool has_point_within(const Eigen::Vector3d& q_w, double distance_m) const;

  LocalMapParams params_;
  std::uint32_t cap_;
  double inv_voxel_;
  tsl::robin_map<CellKey, std::uint32_t, CellKeyHash> cell_slot_;
  std::vector<Voxel> voxels_;          // slots; some free
  std::vector<std::uint32_t> free_slots_;
  std::size_t point_count_ = 0;
  std::uint32_t insert_count_ = 0;
  std::vector<std::uint32_t> new_points_;  // indices inserted by the current insert()
  std::vector<Neighbour> neighbours_;
  std::vector<CellKey> doomed_;
};

}  // namespace tumble
