// What moved leaves the map. A map point that a later beam passes
// through was on something that has since gone: a person walking by, the
// person pulling the cage's rope, a door. Each beam of a registered scan
// removes the map points within beam_radius_m of its line, from min_range_m
// out to margin_m short of its return (the margin covers range noise and the
// pose error), unless
// - a return of the same scan lies within support_radius_m of the point: the
//   surface is still there, and the beam passed its edge (a pillar's corner);
// - the beam grazes the point's own surface (its map normal, fitted for the
//   test where ICP has not yet): a wall seen edge-on, whose points lie within
//   their range noise of a beam that runs along it;
// - the beam grazes the surface it returns from (a floor seen far off) and
//   the point lies on that surface;
// - the point is beyond max_range_m along the beam, where the cost of the
//   walk grows and the people that matter are not.
// Points that stay are still reached by the beams of later scans from other
// places. A point with no surface (too few neighbours, an edge, a line) is
// removed: a person's points are mostly such.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/local_map.hpp"
#include "core/parallel_runner.hpp"
#include "core/point_grid.hpp"

namespace tumble {

struct MapBeam {
  Eigen::Vector3d origin_w = Eigen::Vector3d::Zero();      // the sensor when the point was fired
  Eigen::Vector3d end_w = Eigen::Vector3d::Zero();         // the return
  Eigen::Vector3d end_normal_w = Eigen::Vector3d::Zero();  // the return's surface normal; zero where none
};

struct SeenThroughParams {
  bool enabled = true;
  // The RS-16's beam is 3 mrad wide (a 3 cm spot at 10 m); map points sit
  // within their 2 cm range noise of the surface, and a person's points 5 cm
  // apart. Ours: on a simulated cage run with four walkers and the rope
  // puller (test/core_sim/seen_through_sim_test.cpp, beam_stride 2), 3 cm
  // left 30 % of the walkers' stale points and 16 % of the puller's, 5 cm
  // 13 % and 7 %.
  double beam_radius_m = 0.05;
  double margin_m = 0.5;
  double min_range_m = 0.4;  // the RS-16's minimum range: nearer, the beam saw nothing
  double max_range_m = 30;
  // ScanRegistration casts a beam from every beam_stride-th registered point
  // of a scan, the others' turn coming on the next scans: a person moves a
  // few cm between scans, and the walk is a sixth of a cage scan's time on
  // one core with every beam.
  std::size_t beam_stride = 2;
  // |normal · beam direction| below this: the beam grazes its return's
  // surface, and points within same_surface_m of that plane stay.
  double grazing_cos = 0.3;
  double same_surface_m = 0.15;
  // A point with a return of the same scan this close is still there: a beam
  // that passes the edge of a surface, whose other beams hit it, leaves it.
  double support_radius_m = 0.1;
  // Only a scan whose pose is this sure along every direction removes
  // anything (ScanResult::expected_error_icp_m: registration_confidence.hpp's
  // expected error of the ICP covariance as it is). A pose slipping
  // along a corridor would see through the walls at its ends, the only
  // points that hold it.
  double max_expected_error_m = 0.024;
};

// Throws std::invalid_argument naming the parameter out of range.
void check_seen_through_params(const SeenThroughParams& params);

class SeenThroughRemover {
 public:
  // Beams are walked on `runner`'s threads.
  explicit SeenThroughRemover(const SeenThroughParams& params, ParallelRunner& runner = serial_runner());

  // Removes from `map` the points `beams` see through and no return of
  // `returns_w` (the whole scan, world frame) is near; returns how many.
  std::size_t remove(LocalMap& map, std::span<const MapBeam> beams, std::span<const Eigen::Vector3d> returns_w);

 private:
  SeenThroughParams params_;
  ParallelRunner* runner_;
  std::vector<std::vector<std::uint32_t>> found_;   // per worker
  std::vector<std::vector<Neighbour>> neighbours_;  // per worker
  std::vector<std::uint32_t> doomed_;
  PointGrid returns_;
};

}  // namespace tumble
