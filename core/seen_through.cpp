#include "core/seen_through.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace tumble {

namespace {

// f(cell) for every cell of size 1/inv_cell the segment a→b passes through,
// from a's (Amanatides & Woo's traversal).
template <class F>
void for_each_cell_on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double inv_cell, F&& f) {
  CellKey cell = cell_of(a, inv_cell);
  const CellKey last = cell_of(b, inv_cell);
  const Eigen::Vector3d d = (b - a) * inv_cell;  // in cells
  const Eigen::Vector3d start = a * inv_cell;
  std::int32_t step[3];
  double t_next[3], t_delta[3];
  std::int32_t* coord[3] = {&cell.x, &cell.y, &cell.z};
  for (int k = 0; k < 3; ++k) {
    const double inf = std::numeric_limits<double>::infinity();
    step[k] = d[k] > 0 ? 1 : d[k] < 0 ? -1 : 0;
    t_delta[k] = step[k] == 0 ? inf : std::abs(1.0 / d[k]);
    const double boundary = step[k] > 0 ? std::floor(start[k]) + 1 : std::floor(start[k]);
    t_next[k] = step[k] == 0 ? inf : (boundary - start[k]) / d[k];
  }
  const std::int64_t cells = std::int64_t{1} + std::abs(std::int64_t{last.x} - cell.x) +
                             std::abs(std::int64_t{last.y} - cell.y) + std::abs(std::int64_t{last.z} - cell.z);
  for (std::int64_t visited = 0; visited < cells; ++visited) {
    f(cell);
    const int k = t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
    if (t_next[k] > 1.0) return;
    *coord[k] += step[k];
    t_next[k] += t_delta[k];
  }
}

// The returns' search grid: a support search reaches one or two cells.
constexpr double kReturnsCellM = 0.25;

}  // namespace

void check_seen_through_params(const SeenThroughParams& p) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("SeenThroughParams: " + what); };
  if (!(p.beam_radius_m > 0)) fail("beam_radius_m must be > 0");
  if (!(p.margin_m >= 0)) fail("margin_m must be >= 0");
  if (!(p.min_range_m >= 0)) fail("min_range_m must be >= 0");
  if (!(p.max_range_m > p.min_range_m)) fail("max_range_m must be > min_range_m");
  if (!(p.grazing_cos >= 0 && p.grazing_cos <= 1)) fail("grazing_cos must be in [0, 1]");
  if (!(p.same_surface_m >= 0)) fail("same_surface_m must be >= 0");
  if (!(p.support_radius_m >= 0)) fail("support_radius_m must be >= 0");
  if (!(p.max_expected_error_m > 0)) fail("max_expected_error_m must be > 0");
  if (p.beam_stride < 1) fail("beam_stride must be >= 1");
}

SeenThroughRemover::SeenThroughRemover(const SeenThroughParams& params, ParallelRunner& runner)
    : params_(params), runner_(&runner), found_(runner.workers()), neighbours_(runner.workers()) {
  check_seen_through_params(params);
}

std::size_t SeenThroughRemover::remove(LocalMap& map, std::span<const MapBeam> beams,
                                       std::span<const Eigen::Vector3d> returns_w) {
  if (!params_.enabled || map.empty()) return 0;
  returns_.build(returns_w, kReturnsCellM);
  for (auto& found : found_) found.clear();
  const double inv_cell = 1.0 / map.params().voxel_size_m;
  const double r2 = params_.beam_radius_m * params_.beam_radius_m;
  const LocalMap& searched = map;
  runner_->run(beams.size(), [&](std::size_t worker, std::size_t begin, std::size_t end) {
    std::vector<std::uint32_t>& found = found_[worker];
    for (std::size_t b = begin; b < end; ++b) {
      const MapBeam& beam = beams[b];
      const Eigen::Vector3d ray = beam.end_w - beam.origin_w;
      const double range = ray.norm();
      const double reach = std::min(range - params_.margin_m, params_.max_range_m);
      if (!(reach > params_.min_range_m)) continue;
      const Eigen::Vector3d dir = ray / range;
      const bool grazing =
          beam.end_normal_w.squaredNorm() > 0.5 && std::abs(beam.end_normal_w.dot(dir)) < params_.grazing_cos;
      const Eigen::Vector3d from = beam.origin_w + params_.min_range_m * dir;
      const Eigen::Vector3d to = beam.origin_w + reach * dir;
      const Eigen::Vector3d r = Eigen::Vector3d::Constant(params_.beam_radius_m);
      // Whether the beam passed through map point `index` at p, and nothing says it is still there.
      auto seen_through = [&](std::uint32_t index, const Eigen::Vector3d& p) {
        const Eigen::Vector3d v = p - beam.origin_w;
        const double along = v.dot(dir);
        if (along < params_.min_range_m || along > reach || v.squaredNorm() - along * along > r2) return false;
        if (grazing && std::abs(beam.end_normal_w.dot(p - beam.end_w)) < params_.same_surface_m) return false;
        Neighbour seen;
        if (returns_.knn(p, params_.support_radius_m, std::span<Neighbour>(&seen, 1)) > 0) return false;
        const PlaneFit surface = searched.surface_at(index, neighbours_[worker]);
        return !(surface.valid && std::abs(surface.normal.dot(dir)) < params_.grazing_cos);
      };
      // The cells the beam's line crosses; in each, the points near the
      // stretch of the line inside the cell grown by the beam radius (a
      // point's nearest place on the line may lie in the next cell). A point
      // within the radius in a cell the line does not cross is left to
      // other beams.
      const double cell_m = map.params().voxel_size_m;
      for_each_cell_on_segment(from, to, inv_cell, [&](const CellKey& key) {
        const Eigen::Vector3d lo = Eigen::Vector3d(key.x, key.y, key.z) * cell_m - r;
        const Eigen::Vector3d hi = lo + Eigen::Vector3d::Constant(cell_m + 2 * params_.beam_radius_m);
        double t0 = 0, t1 = 1;
        for (int k = 0; k < 3; ++k) {
          const double step = to[k] - from[k];
          if (step == 0) continue;  // inside the slab: the line crosses the cell
          const double a = (lo[k] - from[k]) / step, b = (hi[k] - from[k]) / step;
          t0 = std::max(t0, std::min(a, b));
          t1 = std::min(t1, std::max(a, b));
        }
        if (t0 > t1) return;
        const Eigen::Vector3d enter = from + t0 * (to - from), leave = from + t1 * (to - from);
        searched.for_each_point_in_cell(key, enter.cwiseMin(leave) - r, enter.cwiseMax(leave) + r,
                                        [&](std::uint32_t index, const Eigen::Vector3d& p) {
                                          if (seen_through(index, p)) found.push_back(index);
                                        });
      });
    }
  });
  doomed_.clear();
  for (const auto& found : found_) doomed_.insert(doomed_.end(), found.begin(), found.end());
  return doomed_.empty() ? 0 : map.remove_points(doomed_);
}

}  // namespace tumble
