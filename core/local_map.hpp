// The rolling local map (docs/method.md §5): registered points in the world
// frame, in a voxel hash (KISS-ICP / iVox style), bounded in space (radius
// around the current pose) and in density (a minimum point spacing and a cap
// per voxel), with the normals and sigmas the weighted point-to-plane ICP uses.
#pragma once

#include <tsl/robin_map.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "core/grid_search.hpp"
#include "core/normals.hpp"
#include "core/parallel_runner.hpp"
#include "core/point_cloud.hpp"

namespace tumble {

struct LocalMapParams {
  // Hash cell, also the search grid; the daemon's defaults. A search that
  // finds few points nearby (sparse rings far away, the normals' 1 m line
  // retries) visits every cell within its radius, so the cell is sized for
  // those; a planar 0.5 m cell at 5 cm spacing holds ~100 points.
  double voxel_size_m = 0.5;
  std::size_t max_points_per_voxel = 100;  // a full voxel takes no more points
  double radius_m = 50;                  // voxels farther from the pose are dropped
  double min_point_distance_m = 0.05;    // no new point this close to a map point
  double max_sigma_s_m = 1.0;            // points less certain than this stay out
  // PCA of the map normals: k = 20 neighbours (the authors' value); see
  // NormalParams for the validity limits.
  NormalParams normals{.k = 20};
};

// What ICP reads of a map point besides its position (kept apart, in the
// chunk's position array the searches scan). Only what ICP needs is kept: the
// map holds millions of points on a long run. The normal is fitted when ICP
// first matches the point (LocalMap::fitted_point), not when it goes in: by
// then later scans have often filled in the surface around it
// (docs/decisions/reading-normals.md), and a point never matched is
// never fitted (5 % of a cage scan's time on one core).
struct MapPoint {
  Eigen::Vector3f normal_w = Eigen::Vector3f::UnitZ();  // set once normal_state is kNormalFitted
  Eigen::Vector3f sensor_w = Eigen::Vector3f::Zero();   // the sensor when the point went in: the
                                                        // fit's line of sight
  double variance_m2 = 0;     // σn² + σs² of the point when it was inserted
  std::uint32_t line_id = 0;  // scan line: insert() call number << 8 | ring
  bool normal_valid = false;
  std::uint8_t normal_state = 0;  // kNormalUnfitted, kNormalFitting or kNormalFitted (atomic_ref)
};
inline constexpr std::uint8_t kNormalUnfitted = 0;
inline constexpr std::uint8_t kNormalFitting = 1;
inline constexpr std::uint8_t kNormalFitted = 2;

struct MapInsertStats {
  std::size_t inserted = 0;
  std::size_t rejected_sigma = 0;     // sigma_s above max_sigma_s_m
  std::size_t rejected_too_close = 0; // a map point within min_point_distance_m
  std::size_t rejected_voxel_full = 0;
};

class LocalMap {
 public:
  // find_insert_candidates() runs on `runner`'s threads.
  explicit LocalMap(const LocalMapParams& params = {}, ParallelRunner& runner = serial_runner());

  // Inserts the points of `cloud` (frame L, rings used for the scan lines)
  // registered at T_wl. Their normals wait for fitted_point().
  MapInsertStats insert(const PointCloud& cloud, const Eigen::Isometry3d& T_wl);

  // Indices of the points of `cloud` (frame L, at T_wl) with no map point
  // within min_point_distance_m: the only ones insert() can take. A scan
  // whose normals and σ's are costly computes them for these alone (in steady
  // state most of a scan lands on mapped surfaces); insert() still checks
  // every point against the points inserted before it. Returns how many.
  std::size_t find_insert_candidates(std::span<const Eigen::Vector3d> points_l, const Eigen::Isometry3d& T_wl,
                                     std::vector<std::uint32_t>& candidates);

  // Drops every voxel whose centre is farther than radius_m from centre_w.
  std::size_t remove_far_from(const Eigen::Vector3d& centre_w);

  // Drops the points of `indices` (repeats allowed); returns how many went.
  // Every other point keeps its data, but indices of points that shared a
  // voxel with a dropped one change.
  std::size_t remove_points(std::span<const std::uint32_t> indices);

  // f(index, position_w) for every point of the cell `key` (voxel_size_m
  // cells) inside the box [lo, hi].
  template <class F>
  void for_each_point_in_cell(const CellKey& key, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, F&& f) const {
    if (!occupancy_.maybe_occupied(key)) return;
    const auto it = cell_slot_.find(key);
    if (it == cell_slot_.end()) return;
    const Slot& slot = slots_[it->second];
    if ((slot.lo.cast<double>().array() > hi.array()).any() || (slot.hi.cast<double>().array() < lo.array()).any())
      return;
    for_each_chunk(slot, [&](const Chunk& chunk, std::uint32_t base, std::uint32_t n) {
      for (std::uint32_t j = 0; j < n; ++j) {
        const Eigen::Vector3d& p = chunk.positions[j];
        if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all()) f(base + j, p);
      }
    });
  }

  // The up to k (0: storage.size()) nearest map points of q_w within
  // max_distance_m, nearest first unless `order` is kAny, at the front of
  // storage; returns how many. Resolve an index with point(). Storage for 2k
  // is faster for large k.
  std::size_t knn(const Eigen::Vector3d& q_w, double max_distance_m, std::span<Neighbour> storage,
                  std::size_t k = 0, KnnOrder order = KnnOrder::kNearestFirst) const;
  // Its normal fields hold once normal_state is kNormalFitted (fitted_point()).
  const MapPoint& point(std::uint32_t index) const { return chunk(index / kChunkPoints).points[index % kChunkPoints]; }
  // The point with its normal: fitted on the first call from the map as it is
  // then (oriented toward the sensor that saw the point), kept for later
  // calls. Existing points keep their normals: a map point is static once
  // registered, and refitting around every insertion would cost O(touched
  // voxels x points) per scan. A cache of the positions, so const: concurrent
  // calls are safe between insert()s, each with its own `neighbours` and
  // `own_fit`. A call that finds another thread fitting the same point fits
  // it into own_fit (the same map, so the same normal) and returns that.
  const MapPoint& fitted_point(std::uint32_t index, std::vector<Neighbour>& neighbours, MapPoint& own_fit) const;
  // The point's surface: its normal where fitted_point() has fitted it, else
  // a fit from the map as it is now that is not kept (the point's own waits
  // for ICP). Safe concurrently with itself and fitted_point() between insert()s.
  PlaneFit surface_at(std::uint32_t index, std::vector<Neighbour>& neighbours) const;
  const Eigen::Vector3d& position(std::uint32_t index) const {
    return chunk(index / kChunkPoints).positions[index % kChunkPoints];
  }

  std::size_t size() const { return point_count_; }
  std::size_t voxel_count() const { return cell_slot_.size(); }
  bool empty() const { return point_count_ == 0; }
  const LocalMapParams& params() const { return params_; }

  // f(position_w) for the first max_per_voxel points of every voxel: the map
  // thinned for a viewer at the cost of a walk over the voxels, not the points.
  template <class F>
  void for_each_voxel_sample(std::uint32_t max_per_voxel, F&& f) const {
    const std::uint32_t per_voxel = std::min(max_per_voxel, kChunkPoints);
    for (const auto& [key, slot] : cell_slot_) {
      const Slot& s = slots_[slot];
      if (s.count == 0) continue;
      const Chunk& first = chunk(s.first_chunk);
      for (std::uint32_t j = 0; j < std::min(s.count, per_voxel); ++j) f(first.positions[j]);
    }
  }

  // f(position_w, point) for every map point (normals as point() says).
  template <class F>
  void for_each_point(F&& f) const {
    for (const auto& [key, slot] : cell_slot_) {
      for_each_chunk(slots_[slot], [&](const Chunk& chunk, std::uint32_t, std::uint32_t n) {
        for (std::uint32_t j = 0; j < n; ++j) f(chunk.positions[j], chunk.points[j]);
      });
    }
  }

 private:
  // A voxel's points live in a chain of fixed-size chunks from one pool: a
  // voxel holds only as many chunks as its points need (most voxels of a
  // 16-ring map hold far fewer than the cap), the pool grows by blocks that
  // never move, and the chunks of dropped voxels are reused, so a map
  // of bounded extent stops allocating. A point's index is its chunk × 16 + slot.
  // 16, not 32: a voxel wastes half a chunk on average, and on the 60 s run
  // (1.25 M points, 33 per voxel) 32-point chunks left 38 % of the pool empty.
  static constexpr std::uint32_t kChunkPoints = 16;
  static constexpr std::uint32_t kBlockChunks = 64;  // the pool grows by this many chunks
  static constexpr std::uint32_t kNoChunk = ~std::uint32_t{0};
  struct Chunk {
    std::array<Eigen::Vector3d, kChunkPoints> positions;  // what the searches scan, contiguous
    std::array<MapPoint, kChunkPoints> points;
    std::uint32_t next = kNoChunk;
  };
  using ChunkBlock = std::array<Chunk, kBlockChunks>;
  Chunk& chunk(std::uint32_t c) { return (*blocks_[c / kBlockChunks])[c % kBlockChunks]; }
  // The normal cache's way into a point from const code (fitted_point).
  MapPoint& cached_point(std::uint32_t index) const {
    return const_cast<Chunk&>(chunk(index / kChunkPoints)).points[index % kChunkPoints];
  }
  PlaneFit fit_normal(std::uint32_t index, const MapPoint& point, std::vector<Neighbour>& neighbours) const;
  const Chunk& chunk(std::uint32_t c) const { return (*blocks_[c / kBlockChunks])[c % kBlockChunks]; }
  struct Slot {
    CellKey key;
    std::uint32_t count = 0;
    std::uint32_t first_chunk = kNoChunk;
    std::uint32_t last_chunk = kNoChunk;
    // Bounds of the voxel's points (floats, rounded outward), so a search
    // for a thin box skips a voxel whose points all lie elsewhere in it: a
    // beam 0.3 m up crosses the floor's voxels all the way to its return.
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
    Eigen::Vector3f hi = Eigen::Vector3f::Constant(-std::numeric_limits<float>::infinity());
  };
  // f(chunk, index of its first point, points used in it) for each chunk of the voxel.
  template <class F>
  void for_each_chunk(const Slot& slot, F&& f) const {
    std::uint32_t left = slot.count;
    for (std::uint32_t c = slot.first_chunk; left > 0;) {
      const Chunk& current = chunk(c);
      const std::uint32_t n = std::min(left, kChunkPoints);
      f(current, c * kChunkPoints, n);
      c = current.next;
      left -= n;
    }
  }
  bool has_point_within(const Eigen::Vector3d& q_w, double distance_m) const;
  std::uint32_t slot_for(const CellKey& key);
  std::uint32_t new_chunk();
  void release(Slot& slot);
  // Widens the slot's bounds to hold p (rounded outward to float).
  static void extend_bounds(Slot& slot, const Eigen::Vector3d& p) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    for (int k = 0; k < 3; ++k) {
      slot.lo[k] = std::min(slot.lo[k], std::nextafter(static_cast<float>(p[k]), -kInf));
      slot.hi[k] = std::max(slot.hi[k], std::nextafter(static_cast<float>(p[k]), kInf));
    }
  }
  void drop_voxel(tsl::robin_map<CellKey, std::uint32_t, CellKeyHash>::iterator it);
  // `doomed`: the voxel's (slot, index) pairs from remove_points(), sorted.
  std::size_t compact_voxel(std::uint32_t slot, std::span<const std::pair<std::uint32_t, std::uint32_t>> doomed);

  LocalMapParams params_;
  ParallelRunner* runner_;
  std::uint32_t cap_;
  double inv_voxel_;
  tsl::robin_map<CellKey, std::uint32_t, CellKeyHash> cell_slot_;
  CellOccupancy occupancy_;  // of cell_slot_'s keys
  std::vector<Slot> slots_;
  std::vector<std::unique_ptr<ChunkBlock>> blocks_;
  std::vector<std::uint32_t> free_chunks_;
  std::vector<std::uint32_t> free_slots_;
  std::size_t point_count_ = 0;
  std::uint32_t insert_count_ = 0;
  std::vector<std::uint8_t> is_candidate_;  // per point of find_insert_candidates()
  std::vector<CellKey> doomed_;
  // remove_points()'s scratch: (slot, index) of the doomed points, and one
  // voxel's chunks in order.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> doomed_points_;
  std::vector<std::uint32_t> voxel_chunks_;
};

}  // namespace tumble
