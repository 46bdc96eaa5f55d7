// `tumble-calib rig`: the lidar-IMU rotation, time offset and lever arm of a
// rig from one recording of both sensors (tools/calib/README.md, "rig").
//  1. Register the scans without the IMU (constant-twist de-skew) for as
//     long as their scan-to-scan rotations agree in magnitude with the
//     gyro's (the start of the motion, before the rates build up); a first
//     rotation from the rotations between every two of those poses up to a
//     second apart, at the best of a grid of shifts (rig_bootstrap.hpp: why
//     it holds). Refused (RigError) when its fits from the even and from the
//     odd poses disagree.
//  2. Register the whole recording de-skewed by the gyro under that
//     estimate; coarse time offset by cross-correlating the rotation
//     magnitudes, then the offset by a fine search of the hand-eye residual,
//     and the rotation at it. Repeat (finer) until the estimate settles.
//  3. The lever arm from the last pass's poses and the accelerometer.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "tools/calib/rig_lever_arm.hpp"
#include "tools/calib/rig_registration.hpp"
#include "tools/calib/rig_rotation.hpp"
#include "tools/calib/rig_time_offset.hpp"

namespace tumble::calib {

struct RigOptions {
  double imu_rate_hz = 100.0;  // the recording's IMU line (used when it has no manifest.yaml)
  std::uint32_t imu_baud = 115200;
  rs16::ClockMode lidar_clock = rs16::ClockMode::Free;  // without manifest.yaml; tumbled's lidar.clock default
  double max_offset_s = 0.3;   // the coarse search: offsets within ±this
  int max_deskewed_passes = 6;  // passes 2.. end when the estimate settles, or after this many
  // The lever arm is reported as observable when its largest 1 σ is within
  // this and the fitted gravity is within max_gravity_error_m_s2 of
  // standard gravity (a check of the lidar's accelerations: registration
  // errors that follow the motion scale them, and bias the arm far beyond
  // its σ, which treats them as independent).
  double max_lever_arm_sigma_m = 0.003;
  double max_gravity_error_m_s2 = 0.05;
};

struct RigPass {
  std::string name;
  std::size_t scans = 0;
  std::size_t scans_registered = 0;
  std::size_t increments = 0;
  TimeOffsetEstimate offset;
  HandEyeRotation rotation;
};

struct RigCalibration {
  std::vector<RigPass> passes;
  HandEyeRotation rotation;            // the last pass's
  TimeOffsetEstimate offset;           // the last pass's
  LeverArmEstimate lever_arm;
  bool lever_arm_observable = false;
  double bootstrap_s = 0.0;                 // how long pass 1 agreed with the gyro
  double bootstrap_weakest_axis_deg = 0.0;  // RMS per scan interval about pass 1's least-turned axis
  std::size_t imu_samples = 0;
};

// Throws InputError for a missing or unusable file (exit 2 in the command),
// RigError when the recording cannot give the calibration (exit 1).
class RigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using RigProgress = std::function<void(const RigPass&)>;
RigCalibration calibrate_rig(const std::filesystem::path& recording_dir, const RigOptions& options,
                             const RigProgress& progress = {});

// The lidar rotations between consecutive registered scans (the gap must be one scan period).
std::vector<LidarRotation> lidar_rotations(std::span<const ScanPose> poses);

}  // namespace tumble::calib
