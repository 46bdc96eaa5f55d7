#include "tools/calib/rig_bootstrap.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "core/angles.hpp"

namespace tumble::calib {
namespace {

// A second of the gentle start turns by tens of degrees about every axis;
// longer pairs would add little and reach the rotation vector's π.
constexpr double kMaxPairGapS = 1.0;
constexpr double kMaxPairAngleRad = 2.0;
// The shifts searched: the constant-twist lag (tens of ms) plus the rig's offset.
constexpr double kLagSearchS = 0.08;
constexpr double kLagStepS = 0.002;
// The refits settle in 4-5 on the simulated mounts; more means a window
// that does not determine the rotation.
constexpr int kMaxRefits = 8;
constexpr double kSettledDeg = 0.05;

bool in_subset(std::size_t index, PoseSubset subset) {
  switch (subset) {
    case PoseSubset::kEven: return index % 2 == 0;
    case PoseSubset::kOdd: return index % 2 == 1;
    case PoseSubset::kAll: break;
  }
  return true;
}

}  // namespace

std::vector<LidarRotation> pose_pair_rotations(std::span<const ScanPose> poses, double max_gap_s,
                                               double max_angle_rad, PoseSubset subset) {
  std::vector<LidarRotation> out;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!poses[i].registered || !in_subset(i, subset)) continue;
    for (std::size_t j = i + 1; j < poses.size() && poses[j].t_s - poses[i].t_s <= max_gap_s; ++j) {
      if (!poses[j].registered || !in_subset(j, subset)) continue;
      const Eigen::AngleAxisd turn(poses[i].T_wl.linear().transpose() * poses[j].T_wl.linear());
      if (turn.angle() >= max_angle_rad) continue;
      out.push_back({poses[i].t_s, poses[j].t_s, turn.angle() * turn.axis()});
    }
  }
  return out;
}

BootstrapRotation bootstrap_rotation(std::span<const ScanPose> poses, std::span<const ImuSample> imu) {
  BootstrapRotation out;
  const std::vector<LidarRotation> pairs = pose_pair_rotations(poses, kMaxPairGapS, kMaxPairAngleRad);
  out.pairs = pairs.size();
  if (pairs.size() < 3) return out;
  // Every pair counts (no outlier rejection): most pairs are at rest, and
  // against their residual the moving ones, whose errors grow with the
  // motion, would all look like outliers. A bad pose shows instead in the
  // halves' disagreement (it is in one half only).
  const auto fit = [&](std::span<const LidarRotation> rotations, double lag_s) {
    return align_rotation_increments(rotation_increments(rotations, imu, lag_s), false);
  };
  // At the grid's best shift alone, a refit jumped by tenths of a degree
  // whenever the best shift flipped to the next step: the parabola's
  // minimum moves smoothly with the poses.
  out.lag_s = fine_time_offset(pairs, imu, 0.0, kLagSearchS, kLagStepS, false).offset_s;
  out.rotation = fit(pairs, out.lag_s);
  const HandEyeRotation even = fit(pose_pair_rotations(poses, kMaxPairGapS, kMaxPairAngleRad, PoseSubset::kEven), out.lag_s);
  const HandEyeRotation odd = fit(pose_pair_rotations(poses, kMaxPairGapS, kMaxPairAngleRad, PoseSubset::kOdd), out.lag_s);
  if (out.rotation.used > 0 && even.used > 0 && odd.used > 0)
    out.halves_disagreement_deg = Eigen::AngleAxisd(even.R_li.transpose() * odd.R_li).angle() * kRadToDeg;
  return out;
}

RefinedBootstrap refine_bootstrap(const BootstrapRotation& start, std::span<const ImuSample> imu,
                                  const WindowRegistration& register_window) {
  RefinedBootstrap out;
  out.fit = start;
  while (out.fit.rotation.used > 0 && out.refits < kMaxRefits) {
    const GyroModel gyro{out.fit.rotation.R_li, GyroTiming{.bias_rad_s = out.fit.rotation.gyro_bias_rad_s}};
    out.poses = register_window(gyro);
    const Eigen::Matrix3d before = out.fit.rotation.R_li;
    out.fit = bootstrap_rotation(out.poses, imu);
    ++out.refits;
    out.last_move_deg = Eigen::AngleAxisd(before.transpose() * out.fit.rotation.R_li).angle() * kRadToDeg;
    if (out.fit.rotation.used > 0 && out.last_move_deg < kSettledDeg) {
      out.settled = true;
      break;
    }
  }
  return out;
}

}  // namespace tumble::calib
