// One calibration run end to end (paper §V-A):
//  1. the reference map: every scan de-skewed and placed with the ground
//     truth, averaged into voxels (the "slowly built" map);
//  2. the odometry as the pipeline runs it: the core ImuFuser fed from the
//     decoded imu.pcap, each scan processed once the IMU covers it (as
//     tumble::Odometry schedules it), de-skewed with the fuser's trajectory,
//     registered by ScanRegistration and fed back to the fuser — so the
//     velocity whose error we measure is the odometry's own, lidar-corrected
//     estimate;
//  3. per scan: the residuals of scan_residual.hpp and the true speed.
// Any unusable input (file missing, corrupt, truncated) ends the run with a
// one-line problem; the bench loop reports it and evaluates the others.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/scan_registration.hpp"
#include "tools/calib/bench_index.hpp"
#include "tools/calib/reference_map.hpp"
#include "tools/calib/scan_residual.hpp"

namespace tumble::calib {

struct CalibParams {
  ReferenceMapParams map;
  ResidualParams residual;
  // The pipeline (core defaults = config/tumbled.yaml defaults). The weight
  // model is NM by default: the trajectory being measured must not depend on
  // the σ_v/σ_ω parameters being fitted (VTW/GVTW weights use them).
  OdometryParams odometry = default_odometry();

  static OdometryParams default_odometry();
};

struct ScanRecord {
  std::uint64_t scan_index = 0;
  double t_start_s = 0;   // since the start of the ground truth
  double duration_s = 0;  // τ: last point − first point
  double speed = 0;       // true mean speed over the scan: m/s (rail) or rad/s (turntable)
  double mean_range_m = 0;
  double residual_m = 0;
  double residual_rms_m = 0;
  std::size_t residual_points = 0;
  double deskew_error_m = 0;
  std::size_t deskew_error_points = 0;
  bool registered = false;     // the registration accepted the scan (its pose corrected the fuser)
  bool saturated = false;      // the IMU clipped during the scan (imu_fuser.hpp, 6: a clipped gyro
                               // axis takes the lidar's rate, a clipped accelerometer adds noise)
  bool before_motion = false;  // ended before the rig first moved (the run's initial rest)
};

struct RunOutcome {
  std::string name;
  Rig rig = Rig::Other;
  bool ok = false;
  std::string problem;  // one line when !ok
  std::vector<ScanRecord> scans;
  std::size_t scans_decoded = 0;
  std::size_t scans_without_trajectory = 0;  // before the fuser's static initialisation, or past the IMU's end
  std::size_t scans_without_truth = 0;       // outside the ground truth's time span
  std::size_t scans_not_registered = 0;
  std::size_t map_points = 0;  // reference map centroids
};

RunOutcome evaluate_run(const BenchRun& run, const CalibParams& params);

}  // namespace tumble::calib
