#include "core/voxel_grid.hpp"

#include <stdexcept>
#include <string>

namespace tumble {

VoxelDownsampler::VoxelDownsampler(double voxel_size_m) : voxel_size_m_(voxel_size_m) {
  if (!(voxel_size_m > 0))
    throw std::invalid_argument("voxel_size_m must be > 0, got " + std::to_string(voxel_size_m));
}

void VoxelDownsampler::apply(const PointCloud& in, PointCloud& out) {
  const double inv = 1.0 / voxel_size_m_;
  cell_slot_.clear();
  best_index_.clear();
  best_distance_sq_.clear();
  for (std::size_t i = 0; i < in.size(); ++i) {
    const Eigen::Vector3d& p = in.points[i];
    const CellKey key = cell_of(p, inv);
    const Eigen::Vector3d centre =
        (Eigen::Vector3d(key.x, key.y, key.z) + Eigen::Vector3d::Constant(0.5)) * voxel_size_m_;
    const double d2 = (p - centre).squaredNorm();
    const auto [it, inserted] = cell_slot_.try_emplace(key, static_cast<std::uint32_t>(best_index_.size()));
    if (inserted) {
      best_index_.push_back(static_cast<std::uint32_t>(i));
      best_distance_sq_.push_back(d2);
    } else if (d2 < best_distance_sq_[it->second]) {
      best_index_[it->second] = static_cast<std::uint32_t>(i);
      best_distance_sq_[it->second] = d2;
    }
  }
  out.resize(best_index_.size());
  for (std::size_t j = 0; j < best_index_.size(); ++j) out.copy_point(j, in, best_index_[j]);
}

}  // namespace tumble
