// The reference the de-skewed scans are compared with: the paper's "dense 3D
// map built slowly" (§V-A). Here it is built from the run's own scans
// de-skewed and placed with the exact ground truth, so it holds no skew and
// no pose error. Points are averaged per small voxel (many scans see each
// voxel, so the centroids lie on the surfaces with the range noise mostly
// averaged out, and one scan's own points weigh little in them). Normals come
// from a coarser grid: the PCA of every point that fell in the coarse cell,
// thousands of them, so the plane is exact however noisy the points; cells
// that hold an edge or a corner (curvature above the limit) have none.
#pragma once

#include <tsl/robin_map.h>

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/grid_search.hpp"
#include "core/normals.hpp"
#include "core/point_grid.hpp"

namespace tumble::calib {

struct ReferenceMapParams {
  double voxel_size_m = 0.05;   // the pipeline's down-sampling cell
  double normal_cell_m = 0.3;   // plane fits over this cell
  double max_curvature = 0.05;  // λ0/Σλ above this: not one plane, no normal
  std::uint32_t min_normal_points = 30;
  double search_cell_m = 0.1;  // grid of the nearest-neighbour search (speed only)
};

struct MapMatch {
  std::uint32_t index = 0;
  double distance_m = 0;
};

class ReferenceMap {
 public:
  explicit ReferenceMap(const ReferenceMapParams& params = {});

  // While building: one point in the world frame.
  void add(const Eigen::Vector3d& p_w);
  // Ends building: centroids, normals and the search grid. Adding afterwards throws.
  void finish();

  std::size_t size() const { return centroids_.size(); }
  const Eigen::Vector3d& centroid(std::uint32_t index) const { return centroids_[index]; }
  // The nearest centroid closer than max_distance_m.
  std::optional<MapMatch> nearest(const Eigen::Vector3d& q_w, double max_distance_m) const;
  // The unit surface normal at a centroid (sign arbitrary); nullopt where its
  // coarse cell is not one plane or has too few points.
  std::optional<Eigen::Vector3d> normal(std::uint32_t index) const;

 private:
  struct VoxelSum {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    std::uint32_t count = 0;
  };
  struct PlaneCell {
    Eigen::Vector3d origin;  // the cell's first point
    CovarianceAccumulator moments;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    bool valid = false;
  };

  ReferenceMapParams params_;
  double inv_voxel_;
  double inv_normal_cell_;
  bool finished_ = false;
  tsl::robin_map<CellKey, std::uint32_t, CellKeyHash> voxel_slot_;
  std::vector<VoxelSum> sums_;
  tsl::robin_map<CellKey, std::uint32_t, CellKeyHash> plane_slot_;
  std::vector<PlaneCell> planes_;
  std::vector<Eigen::Vector3d> centroids_;
  std::vector<std::uint32_t> plane_of_centroid_;
  PointGrid grid_;
};

}  // namespace tumble::calib
