#include "core/local_map.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tumble {

LocalMap::LocalMap(const LocalMapParams& params, ParallelRunner& runner)
    : params_(params),
      runner_(&runner),
      cap_(static_cast<std::uint32_t>(params.max_points_per_voxel)),
      inv_voxel_(1.0 / params.voxel_size_m) {
  if (!(params.voxel_size_m > 0)) throw std::invalid_argument("map voxel_size_m must be > 0");
  if (params.max_points_per_voxel < 1 || params.max_points_per_voxel > 4096)
    throw std::invalid_argument("map max_points_per_voxel must be in [1, 4096], got " +
                                std::to_string(params.max_points_per_voxel));
  if (!(params.radius_m > 0)) throw std::invalid_argument("map radius_m must be > 0");
  if (params.min_point_distance_m < 0) throw std::invalid_argument("map min_point_distance_m must be >= 0");
  if (params.normals.k < 3) throw std::invalid_argument("map normals.k must be >= 3");
}

std::uint32_t LocalMap::new_chunk() {
  if (!free_chunks_.empty()) {
    const std::uint32_t c = free_chunks_.back();
    free_chunks_.pop_back();
    chunk(c).next = kNoChunk;
    return c;
  }
  // A new block: its chunks but the first go to the free list, last out first.
  const auto first = static_cast<std::uint32_t>(blocks_.size() * kBlockChunks);
  blocks_.push_back(std::make_unique<ChunkBlock>());
  for (std::uint32_t c = first + kBlockChunks - 1; c > first; --c) free_chunks_.push_back(c);
  return first;
}

void LocalMap::release(Slot& slot) {
  for (std::uint32_t c = slot.first_chunk; c != kNoChunk; c = chunk(c).next) free_chunks_.push_back(c);
  slot.count = 0;
  slot.first_chunk = slot.last_chunk = kNoChunk;
}

bool LocalMap::has_point_within(const Eigen::Vector3d& q_w, double distance_m) const {
  if (distance_m <= 0) return false;
  const double d2 = distance_m * distance_m;
  const CellKey lo = cell_of(q_w - Eigen::Vector3d::Constant(distance_m), inv_voxel_);
  const CellKey hi = cell_of(q_w + Eigen::Vector3d::Constant(distance_m), inv_voxel_);
  if (hi.x - lo.x > 2 || hi.y - lo.y > 2 || hi.z - lo.z > 2) {  // a radius beyond a voxel: the general search
    Neighbour nearest;
    return knn(q_w, distance_m, std::span<Neighbour>(&nearest, 1)) > 0;
  }
  // The (at most 27, usually 1 to 4) voxels the ball touches; any point inside ends the search.
  for (std::int32_t x = lo.x; x <= hi.x; ++x) {
    for (std::int32_t y = lo.y; y <= hi.y; ++y) {
      for (std::int32_t z = lo.z; z <= hi.z; ++z) {
        const CellKey key{x, y, z};
        if (!occupancy_.maybe_occupied(key)) continue;
        const auto it = cell_slot_.find(key);
        if (it == cell_slot_.end()) continue;
        bool found = false;
        for_each_chunk(slots_[it->second], [&](const Chunk& chunk, std::uint32_t, std::uint32_t n) {
          for (std::uint32_t j = 0; j < n && !found; ++j) found = (chunk.positions[j] - q_w).squaredNorm() < d2;
        });
        if (found) return true;
      }
    }
  }
  return false;
}

std::size_t LocalMap::find_insert_candidates(std::span<const Eigen::Vector3d> points_l, const Eigen::Isometry3d& T_wl,
                                             std::vector<std::uint32_t>& candidates) {
  is_candidate_.resize(points_l.size());
  runner_->run(points_l.size(), [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      is_candidate_[i] = has_point_within(T_wl * points_l[i], params_.min_point_distance_m) ? 0 : 1;
  });
  candidates.clear();
  for (std::size_t i = 0; i < points_l.size(); ++i)
    if (is_candidate_[i]) candidates.push_back(static_cast<std::uint32_t>(i));
  return candidates.size();
}

std::uint32_t LocalMap::slot_for(const CellKey& key) {
  const auto it = cell_slot_.find(key);
  if (it != cell_slot_.end()) return it->second;
  std::uint32_t slot;
  if (!free_slots_.empty()) {
    slot = free_slots_.back();
    free_slots_.pop_back();
  } else {
    slot = static_cast<std::uint32_t>(slots_.size());
    slots_.emplace_back();
  }
  slots_[slot] = Slot{key};
  cell_slot_.emplace(key, slot);
  occupancy_.add(key);
  return slot;
}

MapInsertStats LocalMap::insert(const PointCloud& cloud, const Eigen::Isometry3d& T_wl) {
  MapInsertStats stats;
  const Eigen::Vector3f sensor_w = T_wl.translation().cast<float>();
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
    const std::uint32_t slot = slot_for(cell_of(p_w, inv_voxel_));
    Slot& voxel = slots_[slot];
    if (voxel.count >= cap_) {
      ++stats.rejected_voxel_full;
      continue;
    }
    if (voxel.count % kChunkPoints == 0) {
      const std::uint32_t c = new_chunk();  // may move nothing: `voxel` stays valid
      if (voxel.first_chunk == kNoChunk) {
        voxel.first_chunk = c;
      } else {
        chunk(voxel.last_chunk).next = c;
      }
      voxel.last_chunk = c;
    }
    const std::uint32_t j = voxel.count++ % kChunkPoints;
    Chunk& last = chunk(voxel.last_chunk);
    MapPoint& mp = last.points[j];
    mp = MapPoint{};
    mp.variance_m2 = cloud.sigma_n_m[i] * cloud.sigma_n_m[i] + cloud.sigma_s_m[i] * cloud.sigma_s_m[i];
    mp.line_id = line_base | cloud.rings[i];
    mp.sensor_w = sensor_w;
    last.positions[j] = p_w;
    extend_bounds(voxel, p_w);
    ++stats.inserted;
  }
  point_count_ += stats.inserted;

  return stats;
}

PlaneFit LocalMap::fit_normal(std::uint32_t index, const MapPoint& point, std::vector<Neighbour>& neighbours) const {
  return NormalEstimator::fit_neighbourhood(
      position(index), point.line_id, point.sensor_w.cast<double>(), params_.normals, neighbours,
      [&](const Eigen::Vector3d& q, double radius, std::span<Neighbour> out, std::size_t k) {
        return knn(q, radius, out, k, KnnOrder::kAny);
      },
      [&](std::uint32_t i) -> const Eigen::Vector3d& { return position(i); },
      [&](std::uint32_t i) { return this->point(i).line_id; });
}

PlaneFit LocalMap::surface_at(std::uint32_t index, std::vector<Neighbour>& neighbours) const {
  const MapPoint& mp = point(index);
  const std::atomic_ref<std::uint8_t> state(cached_point(index).normal_state);
  if (state.load(std::memory_order_acquire) == kNormalFitted) {
    PlaneFit fit;
    fit.normal = mp.normal_w.cast<double>();
    fit.valid = mp.normal_valid;
    return fit;
  }
  return fit_normal(index, mp, neighbours);
}

const MapPoint& LocalMap::fitted_point(std::uint32_t index, std::vector<Neighbour>& neighbours,
                                       MapPoint& own_fit) const {
  MapPoint& mp = cached_point(index);
  std::atomic_ref<std::uint8_t> state(mp.normal_state);
  std::uint8_t seen = state.load(std::memory_order_acquire);
  if (seen == kNormalFitted) return mp;
  const bool claimed =
      seen == kNormalUnfitted && state.compare_exchange_strong(seen, kNormalFitting, std::memory_order_acq_rel);
  if (seen == kNormalFitted) return mp;
  MapPoint* target = &mp;
  if (!claimed) {  // another thread is writing mp's normal: copy only what insert() wrote
    own_fit = MapPoint{};
    own_fit.sensor_w = mp.sensor_w;
    own_fit.variance_m2 = mp.variance_m2;
    own_fit.line_id = mp.line_id;
    target = &own_fit;
  }
  const PlaneFit fit = fit_normal(index, *target, neighbours);
  target->normal_w = fit.normal.cast<float>();
  target->normal_valid = fit.valid;
  if (claimed) {
    state.store(kNormalFitted, std::memory_order_release);
  } else {
    own_fit.normal_state = kNormalFitted;
  }
  return *target;
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
    removed += slots_[it->second].count;
    drop_voxel(it);
  }
  point_count_ -= removed;
  return removed;
}

void LocalMap::drop_voxel(tsl::robin_map<CellKey, std::uint32_t, CellKeyHash>::iterator it) {
  const CellKey key = it->first;
  const std::uint32_t slot = it->second;
  release(slots_[slot]);
  free_slots_.push_back(slot);
  cell_slot_.erase(it);
  occupancy_.remove(key);
}

std::size_t LocalMap::remove_points(std::span<const std::uint32_t> indices) {
  // (slot, index), sorted and deduplicated: each voxel's doomed points are
  // one run, in index order (what compact_voxel() searches).
  doomed_points_.clear();
  for (const std::uint32_t index : indices)
    doomed_points_.push_back({cell_slot_.find(cell_of(position(index), inv_voxel_))->second, index});
  std::sort(doomed_points_.begin(), doomed_points_.end());
  doomed_points_.erase(std::unique(doomed_points_.begin(), doomed_points_.end()), doomed_points_.end());
  std::size_t removed = 0;
  for (auto run = doomed_points_.begin(); run != doomed_points_.end();) {
    const std::uint32_t slot = run->first;
    const auto run_end = std::find_if(run, doomed_points_.end(), [&](const auto& d) { return d.first != slot; });
    removed += compact_voxel(slot, std::span(run, run_end));
    if (slots_[slot].count == 0) drop_voxel(cell_slot_.find(slots_[slot].key));
    run = run_end;
  }
  point_count_ -= removed;
  return removed;
}

// Moves the voxel's surviving points to its front, in order, and frees the
// chunks left empty behind them.
std::size_t LocalMap::compact_voxel(std::uint32_t slot, std::span<const std::pair<std::uint32_t, std::uint32_t>> doomed) {
  Slot& voxel = slots_[slot];
  voxel_chunks_.clear();
  for (std::uint32_t c = voxel.first_chunk, left = voxel.count; left > 0; c = chunk(c).next) {
    voxel_chunks_.push_back(c);
    left -= std::min(left, kChunkPoints);
  }
  auto index_of = [&](std::uint32_t k) { return voxel_chunks_[k / kChunkPoints] * kChunkPoints + k % kChunkPoints; };
  std::uint32_t kept = 0;
  voxel.lo.setConstant(std::numeric_limits<float>::infinity());
  voxel.hi.setConstant(-std::numeric_limits<float>::infinity());
  for (std::uint32_t k = 0; k < voxel.count; ++k) {
    const std::uint32_t from = index_of(k);
    if (std::binary_search(doomed.begin(), doomed.end(), std::pair{slot, from})) continue;
    extend_bounds(voxel, position(from));
    const std::uint32_t to = index_of(kept++);
    if (to == from) continue;
    chunk(to / kChunkPoints).positions[to % kChunkPoints] = position(from);
    chunk(to / kChunkPoints).points[to % kChunkPoints] = point(from);
  }
  const std::uint32_t removed = voxel.count - kept;
  voxel.count = kept;
  const std::size_t chunks_kept = (kept + kChunkPoints - 1) / kChunkPoints;
  for (std::size_t k = chunks_kept; k < voxel_chunks_.size(); ++k) free_chunks_.push_back(voxel_chunks_[k]);
  if (chunks_kept == 0) {
    voxel.first_chunk = voxel.last_chunk = kNoChunk;
  } else {
    voxel.last_chunk = voxel_chunks_[chunks_kept - 1];
    chunk(voxel.last_chunk).next = kNoChunk;
  }
  return removed;
}

std::size_t LocalMap::knn(const Eigen::Vector3d& q_w, double max_distance_m, std::span<Neighbour> storage,
                          std::size_t k, KnnOrder order) const {
  if (storage.empty()) return 0;
  KnnResult result(storage, max_distance_m, k);
  grid_knn_search(q_w, params_.voxel_size_m, result, [&](const CellKey& key, KnnResult& res) {
    if (!occupancy_.maybe_occupied(key)) return;
    const auto it = cell_slot_.find(key);
    if (it == cell_slot_.end()) return;
    for_each_chunk(slots_[it->second], [&](const Chunk& chunk, std::uint32_t base, std::uint32_t n) {
      for (std::uint32_t j = 0; j < n; ++j) res.offer((chunk.positions[j] - q_w).squaredNorm(), base + j);
    });
  });
  return result.finish(order);
}

}  // namespace tumble
