#include "tools/calib/reference_map.hpp"

#include <cmath>
#include <stdexcept>

namespace tumble::calib {
namespace {

constexpr std::uint32_t kNoPlane = 0xffffffff;

}  // namespace

ReferenceMap::ReferenceMap(const ReferenceMapParams& params)
    : params_(params), inv_voxel_(1.0 / params.voxel_size_m), inv_normal_cell_(1.0 / params.normal_cell_m) {
  if (!(params.voxel_size_m > 0) || !(params.normal_cell_m > 0) || !(params.search_cell_m > 0))
    throw std::invalid_argument("ReferenceMap: voxel, normal and search cell sizes must be > 0");
}

void ReferenceMap::add(const Eigen::Vector3d& p_w) {
  if (finished_) throw std::logic_error("ReferenceMap::add after finish");
  const auto [voxel, new_voxel] =
      voxel_slot_.try_emplace(cell_of(p_w, inv_voxel_), static_cast<std::uint32_t>(sums_.size()));
  if (new_voxel) sums_.emplace_back();
  VoxelSum& v = sums_[voxel->second];
  v.sum += p_w;
  ++v.count;
  const auto [plane, new_plane] =
      plane_slot_.try_emplace(cell_of(p_w, inv_normal_cell_), static_cast<std::uint32_t>(planes_.size()));
  // The cell's first point is the origin of its moments: keeps them exact far from (0,0,0).
  if (new_plane) planes_.push_back(PlaneCell{p_w, CovarianceAccumulator(p_w)});
  planes_[plane->second].moments.add(p_w);
}

void ReferenceMap::finish() {
  finished_ = true;
  NormalParams limits;
  limits.max_curvature = params_.max_curvature;
  for (PlaneCell& cell : planes_) {
    if (cell.moments.count() < static_cast<int>(params_.min_normal_points)) continue;
    // Viewpoint at the cell's points: no grazing test (the map was seen from
    // many places); the sign is irrelevant to |e·n|.
    const PlaneFit fit = cell.moments.fit(cell.origin, limits);
    cell.valid = fit.valid;
    cell.normal = fit.normal;
  }
  centroids_.resize(sums_.size());
  plane_of_centroid_.resize(sums_.size());
  for (std::size_t i = 0; i < sums_.size(); ++i) {
    centroids_[i] = sums_[i].sum / sums_[i].count;
    // A centroid lies in its voxel, inside one coarse cell, but rounding at a
    // cell boundary may put it in a neighbour that holds no point.
    const auto plane = plane_slot_.find(cell_of(centroids_[i], inv_normal_cell_));
    plane_of_centroid_[i] = plane != plane_slot_.end() ? plane->second : kNoPlane;
  }
  sums_.clear();
  sums_.shrink_to_fit();
  voxel_slot_.clear();
  grid_.build(centroids_, params_.search_cell_m);
}

std::optional<MapMatch> ReferenceMap::nearest(const Eigen::Vector3d& q_w, double max_distance_m) const {
  Neighbour best;
  if (grid_.knn(q_w, max_distance_m, std::span<Neighbour>(&best, 1)) == 0) return std::nullopt;
  return MapMatch{best.index, std::sqrt(best.distance_sq)};
}

std::optional<Eigen::Vector3d> ReferenceMap::normal(std::uint32_t index) const {
  if (plane_of_centroid_[index] == kNoPlane) return std::nullopt;
  const PlaneCell& cell = planes_[plane_of_centroid_[index]];
  if (!cell.valid) return std::nullopt;
  return cell.normal;
}

}  // namespace tumble::calib
