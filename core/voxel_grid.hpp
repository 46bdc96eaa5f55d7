// Voxel-grid down-sampling (algorithm.md §4): one representative per occupied
// cell, the point nearest the cell's centre, with all its attributes (time,
// sigmas, weight) so the weight models still see the original point.
#pragma once

#include <tsl/robin_map.h>

#include <cstdint>
#include <span>
#include <vector>

#include "core/grid_search.hpp"
#include "core/point_cloud.hpp"

namespace tumble {

class VoxelDownsampler {
 public:
  explicit VoxelDownsampler(double voxel_size_m = 0.05);

  // out = the representatives, in the order their cells are first met in `in`
  // (deterministic for a given input); ties go to the earlier point. `out` may
  // not alias `in`. Buffers are kept between calls.
  void apply(const PointCloud& in, PointCloud& out);

  // The indices in `points` of the representatives apply() would keep, in
  // the same order. `indices` is the caller's buffer, reused.
  void select(std::span<const Eigen::Vector3d> points, std::vector<std::uint32_t>& indices);

  double voxel_size_m() const { return voxel_size_m_; }

 private:
  double voxel_size_m_;
  tsl::robin_map<CellKey, std::uint32_t, CellKeyHash> cell_slot_;
  std::vector<std::uint32_t> best_index_;  // per slot: index in `in`
  std::vector<double> best_distance_sq_;   // per slot: its distance to the centre
};

}  // namespace tumble
