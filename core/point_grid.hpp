// A hashed grid over a fixed set of points (one scan's reading), rebuilt per
// scan, for exact k-nearest-neighbour queries. Points are stored cell by cell,
// so a cell's candidates are contiguous in memory.
#pragma once

#include <tsl/robin_map.h>

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "core/grid_search.hpp"

namespace tumble {

class PointGrid {
 public:
  // Indexes `points` (copied). Buffers are kept between builds.
  void build(std::span<const Eigen::Vector3d> points, double cell_size_m);

  // The up to k (0: storage.size()) nearest points of q closer than
  // max_distance_m (finite), nearest first unless `order` is kAny, at the
  // front of storage; returns how many. Neighbour::index is the point's index
  // in the span given to build(). Storage for 2k is faster for large k (see
  // KnnResult).
  std::size_t knn(const Eigen::Vector3d& q, double max_distance_m, std::span<Neighbour> storage,
                  std::size_t k = 0, KnnOrder order = KnnOrder::kNearestFirst) const;

  std::size_t size() const { return sorted_points_.size(); }
  double cell_size_m() const { return cell_size_m_; }

 private:
  struct CellRange {
    std::uint32_t begin = 0;
    std::uint32_t count = 0;
  };
  double cell_size_m_ = 1;
  tsl::robin_map<CellKey, std::uint32_t, CellKeyHash> cell_slot_;
  CellOccupancy occupancy_{16};  // of cell_slot_'s keys
  std::vector<CellRange> ranges_;               // per slot
  std::vector<std::uint32_t> slot_of_point_;    // per input point
  std::vector<Eigen::Vector3d> sorted_points_;  // grouped by cell
  std::vector<std::uint32_t> sorted_index_;     // input index of each sorted point
};

}  // namespace tumble
