// Voxel-grid down-sampling (docs/method.md §4): one representative per occupied
// cell, the point nearest the cell's centre, with all its attributes (time,
// sigmas, weight) so the weight models still see the original point.
#pragma once

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
  // The slot of `key` in the call's cell table, a new one (the next slot) if
  // it has none. The table is open-addressed (linear probing), sized to at
  // least twice the points so probes stay short, holds only slot numbers (a
  // 28.8 k-point scan's table is 256 KiB; the keys are per slot), and is
  // cleared per call by one fill.
  struct Found {
    std::uint32_t slot;
    bool inserted;
  };
  Found find_or_add(const CellKey& key);

  double voxel_size_m_;
  std::vector<std::uint32_t> table_;  // a slot number, or all ones where empty
  std::size_t table_mask_ = 0;
  std::vector<CellKey> slot_keys_;
  std::vector<std::uint32_t> best_index_;  // per slot: index in `in`
  std::vector<double> best_distance_sq_;   // per slot: its distance to the centre
};

}  // namespace tumble
