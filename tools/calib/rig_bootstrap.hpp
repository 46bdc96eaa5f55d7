// Pass 1 of `tumble-calib rig`: the first lidar-IMU rotation, from no
// estimate of anything, good enough for the later passes to settle.
//
// Why it holds (by design, not tuned to a recording):
//  - The lidar-only registration follows only the gentle start, and its
//    poses lag the motion by degrees (a constant-twist de-skew under
//    angular acceleration): their rotation is only a start, 5-20 deg off.
//    So it is refined on a short window of the recording's start: the
//    window registered with the gyro's de-skew under the current
//    estimate, the rotation refitted from its poses, until it settles
//    (refine_bootstrap). A wrongly turned de-skew biases the poses, but ICP
//    takes up only a part of the error, so each refit moves a large
//    fraction of the way to the true rotation: a contraction, whatever the
//    mount (on the synthetic upside-down rig of the test the refits moved
//    it by 4.4 deg, then 0.45, 0.04; on the simulated recordings it settled
//    in 4 refits, 0.02-0.19 deg off: the later passes do the rest).
//  - Each fit uses the rotations between every pair of poses up to a second
//    apart, not only consecutive ones. A pose's orientation error is the
//    same whatever the pair, so a pair's error is bounded by two poses'
//    while its rotation grows with the gap: at the start of a motion a scan
//    interval turns by tenths of a degree about the least-turned axis, a
//    second by tens. r_L = R_LI r_I holds for rotations of any size
//    (R_L = R_LI R_I R_LIᵀ turns the axis and keeps the angle), so the Kabsch
//    fit stays exact for long pairs.
//  - The poses' lag and the rig's unknown clock offset shift the lidar
//    against the gyro in time, so each fit is made at the best shift within
//    ±80 ms: the best of a 2 ms grid, refined by a parabola through it and
//    its neighbours. At the grid's shift alone a refit jumped by 0.4 deg
//    whenever the best shift flipped to the next step, and the refits
//    never settled (clang -O1 and arm64, where last bits differ).
//  - Its own checks: refits that do not settle, or fits from the poses with
//    even and with odd indices (no pose, so no registration error, in
//    common; the same motion) that disagree, mean the window does not
//    determine the rotation: calibrate_rig then fails with one line.
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

// The rotation (and gyro bias) from every pair of registered poses up to
// 1 s apart, at the best shift within ±80 ms (a 2 ms grid refined by a
// parabola); every pair counts.
BootstrapRotation bootstrap_rotation(std::span<const ScanPose> poses, std::span<const ImuSample> imu);

// Refits from start: register_window(the current estimate at offset 0),
// then bootstrap_rotation on its poses, until a refit moves the rotation by
// less than 0.05 deg (at most 8 refits).
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
