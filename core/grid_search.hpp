// Exact nearest-neighbour search over a hashed grid of cubic cells: the one
// search used by the reading's normals, the map's normals and the ICP matcher.
// Cells are visited ring by ring around the query's cell, and a cell is only
// looked up when its box is closer than the current k-th neighbour, so a query
// whose neighbours sit in its own cell costs one or two hash look-ups.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace tumble {

struct CellKey {
  std::int32_t x = 0;
  std::int32_t y = 0;
  std::int32_t z = 0;
  friend bool operator==(const CellKey&, const CellKey&) = default;
};

// splitmix64 finaliser over the packed coordinates: robin_map masks the hash
// with a power of two, so every bit of the hash must depend on every coordinate.
struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const noexcept {
    std::uint64_t h = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.x)) << 42) ^
                      (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.y)) << 21) ^
                      static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.z));
    h ^= h >> 30;
    h *= 0xbf58476d1ce4e5b9ULL;
    h ^= h >> 27;
    h *= 0x94d049bb133111ebULL;
    h ^= h >> 31;
    return static_cast<std::size_t>(h);
  }
};

// Which cells may hold points: a table of counters indexed by the top bits of
// the cell hash, kept next to a grid's hash map. A search visits many cells
// that are empty (large radii on sparse lidar data), and this small table
// (L2-resident) answers those without probing the hash map. Never wrong when
// it says empty; a shared counter only costs a look-up.
class CellOccupancy {
 public:
  explicit CellOccupancy(int bits = 18) : shift_(64 - bits), counts_(std::size_t{1} << bits, 0) {}
  void add(const CellKey& key) { ++counts_[slot(key)]; }
  void remove(const CellKey& key) { --counts_[slot(key)]; }
  bool maybe_occupied(const CellKey& key) const { return counts_[slot(key)] != 0; }

 private:
  std::size_t slot(const CellKey& key) const { return static_cast<std::size_t>(CellKeyHash{}(key) >> shift_); }
  int shift_;
  std::vector<std::uint16_t> counts_;  // a bucket would need 65536 cells to wrap
};

// floor(x) as an int, for -2^31 <= x < 2^31: the same value as std::floor, which
// baseline x86-64 (no SSE4.1 round) calls out of line; the cells of every
// grid here come through it (a third of the down-sampling's time).
inline std::int32_t floor_to_int(double x) {
  const auto truncated = static_cast<std::int32_t>(x);
  return truncated - (x < static_cast<double>(truncated) ? 1 : 0);
}

inline CellKey cell_of(const Eigen::Vector3d& p, double inv_cell_size) {
  return CellKey{floor_to_int(p.x() * inv_cell_size), floor_to_int(p.y() * inv_cell_size),
                 floor_to_int(p.z() * inv_cell_size)};
}

// Whether a search returns its neighbours nearest first or in any order. A
// plane fit does not care, and sorting the 80 of every line refit was 8 % of
// the registration thread's time on the cage runs.
enum class KnnOrder { kNearestFirst, kAny };

// A neighbour found by a search; `index` means what the searched structure says.
struct Neighbour {
  double distance_sq = 0;
  std::uint32_t index = 0;
};

// The k closest candidates offered so far, kept in storage the caller owns
// (so a search never allocates); finish() sorts them by distance (or not: KnnOrder).
// Candidates at or beyond max_distance are refused. k = 0 means
// storage.size(). Small k keeps the list sorted by insertion. Large k (the
// normals' line retries, k = 80, where insertion would shift half the list per
// candidate) collects candidates unsorted when the storage holds 2k of them,
// and keeps the k nearest (nth_element) whenever it fills: O(1) per candidate;
// with less storage it keeps a max-heap, O(log k).
class KnnResult {
 public:
  KnnResult(std::span<Neighbour> storage, double max_distance_m, std::size_t k = 0)
      : k_(k == 0 ? storage.size() : std::min(k, storage.size())),
        storage_(storage.first(k_ > kMaxInsertionK && storage.size() >= 2 * k_ ? 2 * k_ : k_)),
        bound_sq_(k_ == 0 ? 0.0 : max_distance_m * max_distance_m),
        mode_(k_ <= kMaxInsertionK ? Mode::Insertion : storage_.size() > k_ ? Mode::Collect : Mode::Heap) {}

  void offer(double distance_sq, std::uint32_t index) {
    if (distance_sq >= bound_sq_) return;
    if (mode_ == Mode::Collect) {
      storage_[size_++] = Neighbour{distance_sq, index};
      if (size_ == storage_.size()) keep_k_nearest();
      return;
    }
    if (mode_ == Mode::Heap) {
      offer_heap(Neighbour{distance_sq, index});
      return;
    }
    std::size_t i = size_ < storage_.size() ? size_++ : size_ - 1;  // the free slot, or the worst kept
    while (i > 0 && storage_[i - 1].distance_sq > distance_sq) {
      storage_[i] = storage_[i - 1];
      --i;
    }
    storage_[i] = Neighbour{distance_sq, index};
    if (size_ == storage_.size()) bound_sq_ = storage_[size_ - 1].distance_sq;
  }

  // Squared radius inside which a new candidate would still be kept.
  double bound_sq() const { return bound_sq_; }
  std::size_t size() const { return size_; }
  // Leaves the k nearest candidates at the front of the storage, sorted
  // nearest first unless `order` says any order will do; returns how many.
  std::size_t finish(KnnOrder order) {
    if (mode_ == Mode::Collect && size_ > k_) keep_k_nearest();
    if (order == KnnOrder::kAny || mode_ == Mode::Insertion) return size_;
    const auto begin = storage_.begin();
    if (mode_ == Mode::Heap) std::sort_heap(begin, begin + static_cast<std::ptrdiff_t>(size_), nearer);
    if (mode_ == Mode::Collect) std::sort(begin, begin + static_cast<std::ptrdiff_t>(size_), nearer);
    return size_;
  }

 private:
  static constexpr std::size_t kMaxInsertionK = 16;
  enum class Mode { Insertion, Collect, Heap };
  // Collect: the k nearest of the candidates so far move to the front; none
  // beyond the k-th can be kept from now on.
  void keep_k_nearest() {
    const auto begin = storage_.begin();
    const auto kth = begin + static_cast<std::ptrdiff_t>(k_ - 1);
    std::nth_element(begin, kth, begin + static_cast<std::ptrdiff_t>(size_), nearer);
    size_ = k_;
    bound_sq_ = kth->distance_sq;
  }
  // A function object, not a function pointer: the standard algorithms inline it.
  struct Nearer {
    bool operator()(const Neighbour& a, const Neighbour& b) const { return a.distance_sq < b.distance_sq; }
  };
  static constexpr Nearer nearer{};
  void offer_heap(const Neighbour& n) {
    const auto begin = storage_.begin();
    if (size_ < storage_.size()) {
      storage_[size_++] = n;
      std::push_heap(begin, begin + static_cast<std::ptrdiff_t>(size_), nearer);
    } else {
      std::pop_heap(begin, begin + static_cast<std::ptrdiff_t>(size_), nearer);
      storage_[size_ - 1] = n;
      std::push_heap(begin, begin + static_cast<std::ptrdiff_t>(size_), nearer);
    }
    if (size_ == storage_.size()) bound_sq_ = storage_.front().distance_sq;
  }

  std::size_t k_;
  std::span<Neighbour> storage_;
  double bound_sq_;  // max distance² until k are kept, then the k-th distance² (Collect: at the last compaction)
  std::size_t size_ = 0;
  Mode mode_;
};

// The 26 cells around a cell: faces, edges, corners.
inline constexpr std::array<std::array<std::int8_t, 3>, 26> kRing1ByDistanceClass = [] {
  std::array<std::array<std::int8_t, 3>, 26> cells{};
  std::size_t n = 0;
  for (int axes = 1; axes <= 3; ++axes)
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if ((dx != 0) + (dy != 0) + (dz != 0) == axes)
            cells[n++] = {static_cast<std::int8_t>(dx), static_cast<std::int8_t>(dy), static_cast<std::int8_t>(dz)};
  return cells;
}();

// Offers to `result` the points of every cell that can hold one of the k
// nearest neighbours of q. visit_cell(const CellKey&, KnnResult&) offers the
// points of one cell (it is called only for cells that may matter).
template <class VisitCell>
void grid_knn_search(const Eigen::Vector3d& q, double cell_size_m, KnnResult& result, VisitCell&& visit_cell) {
  if (result.bound_sq() <= 0) return;  // k = 0 or a zero radius: nothing can be kept
  const double inv = 1.0 / cell_size_m;
  const Eigen::Vector3d qc = q * inv;
  const CellKey base = cell_of(q, inv);
  // Query position inside its own cell, in cell units, in [0, 1).
  const double rx = qc.x() - base.x, ry = qc.y() - base.y, rz = qc.z() - base.z;
  const double face = std::min({rx, 1 - rx, ry, 1 - ry, rz, 1 - rz});
  const double h2 = cell_size_m * cell_size_m;
  // Gap, in cell units, between the query and the slab of cells at offset d.
  auto gap = [](int d, double r) { return d > 0 ? d - r : (d < 0 ? r + (-d) - 1 : 0.0); };

  visit_cell(base, result);
  // Ring 1 (where nearly every query ends): the 6 face cells, then the 12
  // edge cells, then the 8 corners, each looked up only while closer than
  // the current k-th neighbour. Nearer classes first shrink that bound early,
  // at no per-query sorting cost.
  const double gx2[3] = {gap(-1, rx) * gap(-1, rx) * h2, 0.0, gap(1, rx) * gap(1, rx) * h2};
  const double gy2[3] = {gap(-1, ry) * gap(-1, ry) * h2, 0.0, gap(1, ry) * gap(1, ry) * h2};
  const double gz2[3] = {gap(-1, rz) * gap(-1, rz) * h2, 0.0, gap(1, rz) * gap(1, rz) * h2};
  for (const std::array<std::int8_t, 3>& d : kRing1ByDistanceClass) {
    if (gx2[d[0] + 1] + gy2[d[1] + 1] + gz2[d[2] + 1] >= result.bound_sq()) continue;
    visit_cell(CellKey{base.x + d[0], base.y + d[1], base.z + d[2]}, result);
  }
  // Cells beyond the search radius are never needed (callers pass a finite
  // radius; the cap only keeps the ring count an int).
  const double radius_cells = std::min(std::sqrt(result.bound_sq()) * inv, 1.0e6);
  const int max_ring = static_cast<int>(std::ceil(radius_cells)) + 1;
  for (int ring = 2; ring <= max_ring; ++ring) {
    const double ring_gap = (ring - 1) + face;  // no cell of this ring is closer
    if (ring_gap * ring_gap * h2 >= result.bound_sq()) break;
    for (int dx = -ring; dx <= ring; ++dx) {
      const double gx = gap(dx, rx);
      const double gx2 = gx * gx * h2;
      if (gx2 >= result.bound_sq()) continue;
      for (int dy = -ring; dy <= ring; ++dy) {
        const double gy = gap(dy, ry);
        const double gxy2 = gx2 + gy * gy * h2;
        if (gxy2 >= result.bound_sq()) continue;
        const bool on_shell_xy = (dx == -ring || dx == ring || dy == -ring || dy == ring);
        // Inside the shell only the two z faces belong to this ring.
        const int dz_step = on_shell_xy ? 1 : 2 * ring;
        for (int dz = -ring; dz <= ring; dz += dz_step) {
          const double gz = gap(dz, rz);
          if (gxy2 + gz * gz * h2 >= result.bound_sq()) continue;
          visit_cell(CellKey{base.x + dx, base.y + dy, base.z + dz}, result);
        }
      }
    }
  }
}

}  // namespace tumble
