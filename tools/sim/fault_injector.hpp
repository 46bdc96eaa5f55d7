// Rewrites a `tumble-sim run` folder with faults (`tumble-sim faults`):
// lidar.pcap and imu.pcap through the project's own pcap code, the ground
// truth and manifest carried over, and faults.yaml saying what was done.
// The same plan and seed give the same bytes.
#pragma once

#include <cstdint>
#include <filesystem>

#include "tools/sim/fault_plan.hpp"

namespace tumble::sim {

inline constexpr const char* kFaultsName = "faults.yaml";
// The sender of --foreign-lidar and --second-lidar datagrams (not the lidar's 192.168.1.200).
inline constexpr std::uint32_t kForeignLidarIp = 0xC0A801C9;  // 192.168.1.201

struct FaultCounts {
  std::uint64_t msop_packets = 0;  // in the source run
  std::uint64_t difop_packets = 0;
  std::uint64_t lidar_gap_dropped = 0;     // datagrams (MSOP or DIFOP) removed by --lidar-gap
  std::uint64_t lidar_clock_jumped = 0;    // datagrams whose header time was moved
  std::uint64_t lidar_dropped = 0;         // MSOP packets lost
  std::uint64_t lidar_duplicated = 0;      // MSOP packets sent twice
  std::uint64_t lidar_swapped_pairs = 0;   // neighbouring MSOP packets that changed places
  std::uint64_t lidar_foreign = 0;         // datagrams added from kForeignLidarIp
  std::uint64_t lidar_delayed = 0;         // datagrams that arrive later than recorded
  std::uint64_t lidar_stalls = 0;          // of them, the stalls that held back those after
  double lidar_mean_delay_s = 0.0;
  double lidar_max_delay_s = 0.0;
  std::uint64_t imu_reads = 0;             // in the source run
  std::uint64_t imu_gap_dropped = 0;       // serial reads removed by --imu-gap
  std::uint64_t imu_garbled_reads = 0;     // reads preceded by garbage
  std::uint64_t imu_garbage_bytes = 0;
  std::uint64_t imu_nan_frames = 0;        // MTData2 frames given a NaN rate of turn
  std::uint64_t lidar_stalled = 0;         // MSOP packets with the head held still
  std::uint64_t lidar_second_sender = 0;   // datagrams added from the second host
  std::uint64_t difop_recalibrated = 0;    // DIFOPs given another calibration
  double run_start_s = 0.0;  // host time of the run's first record: T = 0 of the plan
};

// Throws std::invalid_argument for a bad plan or when out_dir is run_dir, and
// std::runtime_error (naming the file) when the run cannot be read or written.
FaultCounts inject_faults(const std::filesystem::path& run_dir, const std::filesystem::path& out_dir,
                          const FaultPlan& plan);

}  // namespace tumble::sim
