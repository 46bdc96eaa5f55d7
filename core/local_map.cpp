#include "core/local_map.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace tumble {

LocalMap::LocalMap(const LocalMapParams& params)
    : params_(params),
      cap_(static_cast<std::uint32_t>(params.max_points_per_voxel)),
      inv_voxel_(1.0 / params.voxel_size_m) {
  if (!(params.voxel_size_m > 0)) throw std::invalid_argument("map voxel_size_m must be > 0");
  if (params.max_points_per_voxel < 1 || params.max_points_per_voxel > 4096)
    throw std::invalid_argument("map max_points_per_voxel must be in [1, 4096], got " +
                                std::to_string(params.max_points_per_voxel));
  if (!(params.radius_m > 0)) throw std::invalid_argument("map radius_m must be > 0");
  if (params.min_point_distance_m < 0) throw std::invalid_argument("map min_point_distance_m must be >= 0");
  if (params.normals.k < 3) throw std::invalid_argument("map normals.k must be >= 3");
  neighbours_.reserve(static_cast<std::size_t>(std::max(params.normals.k, params.normals.line_retry_k)));
}

void LocalMap::clear() {
  for (const auto& [key, slot] : cell_slot_) {
    voxels_[slot].points.clear();
    free_slots_.push_back(slot);
  }
  cell_slot_.clear();
  point_count_ = 0;
}

bool LocalMap::has_point_within(const Eigen::Vector3d& q_w, double distance_m) const {
  if (distance_m <= 0) return false;
  Neighbour nearest;
  return knn(q_w, distance_m, std::span<Neighbour>(&nearest, 1)) > 0;
}

MapInsertStats LocalMap::insert(const PointCloud& cloud, const Eigen::Isometry3d& T_wl) {
  MapInsertStats stats;
  new_points_.clear();
  const std::uint32_t line_base = (insert_count_++ & 0xFFFFFFu) << 8;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!(cloud.sigma_s_m[i] <= params_.max_sigma_s_m)) {  // NaN and inf count as too uncertain
      ++stats.rejected_sigma;
      continue;
    }
    const Eigen::Vector3d p_w = T_wl * cloud.points[i];
    if (has_point_within(p_w, params_.min_point_distance_m)) {
      ++stats.rejected_too_close;
      continue;
    }
    const CellKey key = cell_of(p_w, inv_voxel_);
    auto it = cell_slot_.find(key);
    if (it == cell_slot_.end()) {
      std::uint32_t slot;
      if (!free_slots_.empty()) {
        slot = free_slots_.back();
        free_slots_.pop_back();
      } else {
        slot = static_cast<std::uint32_t>(voxels_.size());
        voxels_.emplace_back();
        voxels_.back().points.reserve(cap_);
      }
      voxels_[slot].key = key;
      it = cell_slot_.emplace(key, slot).first;
    }
    Voxel& voxel = voxels_[it->second];
    if (voxel.points.size() >= cap_) {
      ++stats.rejected_voxel_full;
      continue;
    }
    MapPoint mp;
    mp.p_w = p_w;
    mp.sigma_n_m = cloud.sigma_n_m[i];
    mp.sigma_s_m = cloud.sigma_s_m[i];
    mp.line_id = line_base | cloud.rings[i];
    new_points_.push_back(it->second * cap_ + static_cast<std::uint32_t>(voxel.points.size()));
    voxel.points.push_back(mp);
    ++stats.inserted;
  }
  point_count_ += stats.inserted;

  const Eigen::Vector3d sensor_w = T_wl.translation();
  for (const std::uint32_t index : new_points_) {
    MapPoint& mp = voxels_[index / cap_].points[index % cap_];
    const PlaneFit fit = NormalEstimator::fit_neighbourhood(
        mp.p_w, mp.line_id, sensor_w, params_.normals, neighbours_,
        [&](const Eigen::Vector3d& q, double radius, std::span<Neighbour> out) { return knn(q, radius, out); },
        [&](std::uint32_t i) -> const Eigen::Vector3d& { return point(i).p_w; },
        [&](std::uint32_t i) { return point(i).line_id; });
    mp.normal_w = fit.normal;
    mp.curvature = fit.curvature;
    mp.normal_valid = fit.valid;
  }
  return stats;
}

std::size_t LocalMap::remove_far_from(const Eigen::Vector3d& centre_w) {
  const double r2 = params_.radius_m * params_.radius_m;
  doomed_.clear();
  for (const auto& [key, slot] : cell_slot_) {
    const Eigen::Vector3d c =
        (Eigen::Vector3d(key.x, key.y, key.z) + Eigen::Vector3d::Constant(0.5)) * params_.voxel_size_m;
    if ((c - centre_w).squaredNorm() > r2) doomed_.push_back(key);
  }
  std::size_t removed = 0;
  for (const CellKey& key : doomed_) {
    const auto it = cell_slot_.find(key);
    const std::uint32_t slot = it->second;
    removed += voxels_[slot].points.size();
    voxels_[slot].points.clear();
    free_slots_.push_back(slot);
    cell_slot_.erase(it);
  }
  point_count_ -= removed;
  return removed;
}

std::size_t LocalMap::knn(const Eigen::Vector3d& q_w, double max_distance_m, std::span<Neighbour> storage) const {
  if (storage.empty()) return 0;
  KnnResult result(storage, max_distance_m);
  grid_knn_search(q_w, params_.voxel_size_m, result, [&](const CellKey& key, KnnResult& res) {
    const auto it = cell_slot_.find(key);
    if (it == cell_slot_.end()) return;
    const std::uint32_t base = it->second * cap_;
    const std::vector<MapPoint>& pts = voxels_[it->second].points;
    for (std::size_t j = 0; j < pts.size(); ++j)
      res.offer((pts[j].p_w - q_w).squaredNorm(), base + static_cast<std::uint32_t>(j));
  });
  return result.size();
}

}  // namespace tumble
