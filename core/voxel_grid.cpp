#include "core/voxel_grid.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <utility>

namespace tumble {

namespace {
constexpr std::uint32_t kNoSlot = ~std::uint32_t{0};
}  // namespace

VoxelDownsampler::VoxelDownsampler(double voxel_size_m) : voxel_size_m_(voxel_size_m) {
  if (!(voxel_size_m > 0))
    throw std::invalid_argument("voxel_size_m must be > 0, got " + std::to_string(voxel_size_m));
}

VoxelDownsampler::Found VoxelDownsampler::find_or_add(const CellKey& key) {
  for (std::size_t at = CellKeyHash{}(key) & table_mask_;; at = (at + 1) & table_mask_) {
    const std::uint32_t slot = table_[at];
    if (slot == kNoSlot) {
      table_[at] = static_cast<std::uint32_t>(slot_keys_.size());
      slot_keys_.push_back(key);
      return {table_[at], true};
    }
    if (slot_keys_[slot] == key) return {slot, false};
  }
}

void VoxelDownsampler::select(std::span<const Eigen::Vector3d> points, std::vector<std::uint32_t>& indices) {
  const double inv = 1.0 / voxel_size_m_;
  std::size_t capacity = 64;
  while (capacity < 2 * points.size()) capacity *= 2;
  if (table_.size() < capacity) table_.resize(capacity);
  table_mask_ = capacity - 1;
  std::fill(table_.begin(), table_.begin() + static_cast<std::ptrdiff_t>(capacity), kNoSlot);
  slot_keys_.clear();
  indices.clear();
  best_distance_sq_.clear();
  // The cell of point i − kRecentPeriod, checked before the hash map: in a
  // lidar scan in firing order (RS-16: 16 lasers per firing) that is the same
  // laser one firing earlier, a few millimetres away, usually in the same cell.
  constexpr std::size_t kRecentPeriod = 16;
  std::array<std::pair<CellKey, std::uint32_t>, kRecentPeriod> recent;
  recent.fill({CellKey{}, kNoSlot});
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& p = points[i];
    const CellKey key = cell_of(p, inv);
    const Eigen::Vector3d centre =
        (Eigen::Vector3d(key.x, key.y, key.z) + Eigen::Vector3d::Constant(0.5)) * voxel_size_m_;
    const double d2 = (p - centre).squaredNorm();
    auto& [recent_key, recent_slot] = recent[i % kRecentPeriod];
    std::uint32_t slot;
    if (recent_slot != kNoSlot && recent_key == key) {
      slot = recent_slot;
    } else {
      const auto [found_slot, inserted] = find_or_add(key);
      slot = found_slot;
      recent_key = key;
      recent_slot = slot;
      if (inserted) {
        indices.push_back(static_cast<std::uint32_t>(i));
        best_distance_sq_.push_back(d2);
        continue;
      }
    }
    if (d2 < best_distance_sq_[slot]) {
      indices[slot] = static_cast<std::uint32_t>(i);
      best_distance_sq_[slot] = d2;
    }
  }
}

void VoxelDownsampler::apply(const PointCloud& in, PointCloud& out) {
  select(in.points, best_index_);
  out.resize(best_index_.size());
  for (std::size_t j = 0; j < best_index_.size(); ++j) out.copy_point(j, in, best_index_[j]);
}

}  // namespace tumble
