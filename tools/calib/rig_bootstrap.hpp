// Pass 1 of `tumble-calib rig`: the first lidar-IMU rotation, from the
// lidar-only poses of the recording's gentle start (before the lidar-only
// registration loses the motion), with no estimate of anything to start from.
//
// Why it holds (not tuned to a recording):
//  - It fits the rotation to the scan-to-scan rotations of every pair of
//    poses up to a second apart, not only of consecutive scans. A pose's
//    orientation error (ICP noise, the constant-twist lag) is the same
//    whatever the pair, so a pair's error is bounded by two poses' errors
//    while its rotation grows with the gap: at the start of a motion a
//    scan interval turns by tenths of a degree about the least-turned axis,
//    a second by tens. The fit's conditioning grows with the gap, not with
//    how long the lidar-only registration lasted.
//  - r_L = R_LI r_I holds for rotations of any size (R_L = R_LI R_I R_LIᵀ
//    turns the rotation axis and keeps the angle), so long pairs need no
//    small-angle approximation: the Kabsch fit stays exact.
//  - The poses lag the motion (the constant-twist de-skew) and the rig's
//    clock offset is unknown: both shift the lidar against the gyro in
//    time, so the fit is made at the best of a grid of shifts.
//  - Its own check: the poses with even indices and those with odd ones
//    share no pose, so no registration error; each gives a fit over the
//    same motion, and their disagreement measures the fit's error from the
//    data alone. calibrate_rig refuses a bootstrap whose halves disagree.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "core/types.hpp"
#include "tools/calib/rig_registration.hpp"
#include "tools/calib/rig_rotation.hpp"
#include "tools/calib/rig_time_offset.hpp"

namespace tumble::calib {

enum class PoseSubset { kAll, kEven, kOdd };

// The lidar's rotation between every two registered poses of the subset
// (indices into poses) at most max_gap_s apart, whose rotation is below
// max_angle_rad (far from the rotation vector's ambiguity at π).
std::vector<LidarRotation> pose_pair_rotations(std::span<const ScanPose> poses, double max_gap_s,
                                               double max_angle_rad, PoseSubset subset = PoseSubset::kAll);

struct BootstrapRotation {
  HandEyeRotation rotation;               // over every pair, at lag_s
  double lag_s = 0.0;                     // the shift of the gyro under which the lidar agrees best
  std::size_t pairs = 0;
  double halves_disagreement_deg = 180.0; // the even poses' fit against the odd poses' (180: either failed)
};

BootstrapRotation bootstrap_rotation(std::span<const ScanPose> poses, std::span<const ImuSample> imu);

// The lidar-only poses lag the motion by degrees (their de-skew), so their
// rotation is only a start, 5-20 deg off. It is refined on a short window
// of the recording's gentle start: the window registered with the gyro's
// de-skew under the current estimate (at offset 0), the rotation refitted,
// until it moves by less than 0.05 deg. A wrongly turned de-skew biases the
// poses, but ICP takes up only a part of it, so each refit moves a large
// fraction of the way to the true rotation (on the upside-down mount 16
// deg, then 1.5, 0.1, 0.02).
using WindowRegistration = std::function<std::vector<ScanPose>(const GyroModel&)>;

struct RefinedBootstrap {
  BootstrapRotation fit;          // the last refit's
  std::vector<ScanPose> poses;    // the window's, from the last registration
  int refits = 0;
  double last_move_deg = 180.0;
  bool settled = false;           // false: still moving after the most refits allowed, or a fit failed
};

RefinedBootstrap refine_bootstrap(const BootstrapRotation& start, std::span<const ImuSample> imu,
                                  const WindowRegistration& register_window);

}  // namespace tumble::calib
