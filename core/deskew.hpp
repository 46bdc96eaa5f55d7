// De-skewing (paper eq. 1, docs/method.md §2): every point, measured in the
// lidar frame at its own firing time t_i, is expressed in the lidar frame at
// the scan's first point time t_1:  p̂_i = T_WL(t_1)⁻¹ · T_WL(t_i) · p_i,
// with T_WL(t) interpolated from the fuser's trajectory (linear position,
// slerp rotation). Only the motion inside the scan matters, so a rigid
// re-anchoring of the trajectory by a registration correction leaves the
// result unchanged.
//
// De-skewing is a switch (config `deskew`), because the paper's evaluation
// compares both arms; when off, the scan is only converted to the same output.
//
// Per-point cost: O(1) with the points in (nearly) firing order; no allocation
// (the caller owns the output buffer).
#pragma once

#include <span>

#include <Eigen/Core>

#include "core/trajectory.hpp"
#include "core/types.hpp"

namespace tumble {

// out_points[i] = T(t_ref)⁻¹ T(times_s[i]) points_l[i]. out_points may be the
// same storage as points_l. Sizes must match (std::invalid_argument).
void deskew_points(std::span<const Eigen::Vector3d> points_l, std::span<const double> times_s, double t_ref_s,
                   const Trajectory& trajectory, std::span<Eigen::Vector3d> out_points);

// The scan's points as doubles in the lidar frame at scan.points.front().t_s
// (enabled), or as measured (disabled; the trajectory is then not read).
// out_points.size() must equal scan.points.size().
void deskew_scan(const Scan& scan, const Trajectory& trajectory, bool enabled, std::span<Eigen::Vector3d> out_points);

}  // namespace tumble
