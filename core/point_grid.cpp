#include "core/point_grid.hpp"

#include <stdexcept>
#include <string>

namespace tumble {

void PointGrid::build(std::span<const Eigen::Vector3d> points, double cell_size_m) {
  if (!(cell_size_m > 0)) throw std::invalid_argument("PointGrid cell size must be > 0, got " + std::to_string(cell_size_m));
  cell_size_m_ = cell_size_m;
  const double inv = 1.0 / cell_size_m;
  for (const auto& [key, slot] : cell_slot_) occupancy_.remove(key);
  cell_slot_.clear();
  ranges_.clear();
  slot_of_point_.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [it, inserted] = cell_slot_.try_emplace(cell_of(points[i], inv), static_cast<std::uint32_t>(ranges_.size()));
    if (inserted) {
      ranges_.push_back(CellRange{});
      occupancy_.add(it->first);
    }
    ++ranges_[it->second].count;
    slot_of_point_[i] = it->second;
  }
  std::uint32_t begin = 0;
  for (CellRange& r : ranges_) {
    r.begin = begin;
    begin += r.count;
    r.count = 0;  // refilled below, as the write cursor
  }
  sorted_points_.resize(points.size());
  sorted_index_.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    CellRange& r = ranges_[slot_of_point_[i]];
    sorted_points_[r.begin + r.count] = points[i];
    sorted_index_[r.begin + r.count] = static_cast<std::uint32_t>(i);
    ++r.count;
  }
}

std::size_t PointGrid::knn(const Eigen::Vector3d& q, double max_distance_m, std::span<Neighbour> storage,
                           std::size_t k, KnnOrder order) const {
  if (storage.empty()) return 0;
  KnnResult result(storage, max_distance_m, k);
  grid_knn_search(q, cell_size_m_, result, [&](const CellKey& key, KnnResult& res) {
    if (!occupancy_.maybe_occupied(key)) return;
    const auto it = cell_slot_.find(key);
    if (it == cell_slot_.end()) return;
    const CellRange r = ranges_[it->second];
    for (std::uint32_t j = r.begin; j < r.begin + r.count; ++j)
      res.offer((sorted_points_[j] - q).squaredNorm(), sorted_index_[j]);
  });
  return result.finish(order);
}

}  // namespace tumble
