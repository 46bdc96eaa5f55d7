// One registration pass over a rig recording's lidar scans that does not
// trust the IMU's placement: with an unknown extrinsic the fuser's
// prediction would mislead ICP, so each scan's initial pose is a
// constant-velocity prediction from the previous registered poses.
//  - Without a gyro model (pass 1), scans are de-skewed at that constant
//    twist. It lags the motion by about a scan interval, so under angular
//    acceleration the poses lag (by ~α·τ² rad) and, at hand-waving rates,
//    the errors feed back through the next twist until ICP loses the map:
//    pass 1 is only trusted while it agrees with the gyro (see `stop`).
//  - With a gyro model (an estimate of R_LI, time offset and bias), scans
//    are de-skewed by the gyro's rotation and a constant velocity.
// Poses are those at each scan's first point. The recording's first scan
// (a part of a turn) and scans with less than half the points of the
// fullest so far are left out.
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "core/scan_registration.hpp"
#include "core/types.hpp"
#include "drivers/rs16/decoder.hpp"
#include "tools/calib/rig_gyro.hpp"

namespace tumble::calib {

struct ScanPose {
  double t_s = 0.0;  // the time the pose is for
  double t_scan_start_s = 0.0;
  double t_scan_end_s = 0.0;
  Eigen::Isometry3d T_wl = Eigen::Isometry3d::Identity();
  bool registered = false;  // false: the prediction (ICP failed, or the map's first scan)
};

struct GyroModel {
  Eigen::Matrix3d R_li = Eigen::Matrix3d::Identity();
  GyroTiming timing;
};

// The registration the calibration runs: NM weights (no speed model to
// trust yet), the daemon's scan-line normals.
OdometryParams rig_registration_params();

// Called after every scan with the poses so far; true ends the pass.
using StopCheck = std::function<bool(const std::vector<ScanPose>&)>;

// Throws InputError when the lidar recording is unusable (run_inputs.hpp).
std::vector<ScanPose> register_rig_scans(const std::filesystem::path& lidar_pcap, rs16::ClockMode lidar_clock,
                                         std::span<const ImuSample> imu,
                                         const std::optional<GyroModel>& gyro, const OdometryParams& params,
                                         std::span<const ScanPose> previous = {}, const StopCheck& stop = {});

}  // namespace tumble::calib
