// One bench run's recordings as the calibration reads them: the manifest
// (extrinsic and IMU line settings the fuser and the MTi stream need), the
// IMU recording decoded by the driver, and the lidar recording decoded scan
// by scan. Anything unusable throws InputError naming the file, so the bench
// loop can report the run and go on.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "core/types.hpp"
#include "drivers/rs16/decoder.hpp"

namespace tumble::calib {

// The recording's settings (tumble-sim's manifest.yaml).
struct RunSetup {
  Eigen::Isometry3d T_li = Eigen::Isometry3d::Identity();  // extrinsics.T_LI: p_L = T_LI p_I
  // The simulator writes host time into the lidar's header (a synced clock);
  // a real lidar without PTP or GPS counts from its own power-up (free).
  rs16::ClockMode lidar_clock = rs16::ClockMode::Synced;
  double imu_rate_hz = 100.0;                              // imu.rate_hz
  std::uint32_t imu_baud = 115200;                         // imu.baud
};

// Throws InputError naming the file and the missing or bad key.
RunSetup read_run_setup(const std::filesystem::path& manifest_path);

// Every IMU sample of the recording in time order, timed by the driver's
// TimeMapper (host clock). Throws InputError when the file is missing, is
// not an MTi stream, is truncated or holds corrupt frames, or has no sample.
std::vector<ImuSample> read_imu_samples(const std::filesystem::path& path, const RunSetup& setup);

// Decodes the lidar recording (RS-16 pcap; a free clock is mapped to the
// recorded arrival times, as tumbled maps it) and hands every non-empty scan
// to on_scan, in order. Returns the number of scans. Throws InputError when
// the file is missing or unreadable, ends in a truncated record, holds
// corrupt packets, or yields no scan.
std::size_t for_each_scan(const std::filesystem::path& path, rs16::ClockMode clock,
                          const std::function<void(const Scan&)>& on_scan);

}  // namespace tumble::calib
