// Writes one run into a folder: lidar.pcap (the RS-16's UDP traffic as
// tcpdump records it), imu.pcap (the MTi's serial reads, LINKTYPE_USER0),
// ground_truth.tum (the lidar pose T_WL on the host clock) and manifest.yaml
// (everything needed to interpret or regenerate them).
#pragma once

#include <cstdint>
#include <filesystem>

#include "tools/sim/sim_run.hpp"

namespace tumble::sim {

inline constexpr const char* kLidarPcapName = "lidar.pcap";
inline constexpr const char* kImuPcapName = "imu.pcap";
inline constexpr const char* kGroundTruthName = "ground_truth.tum";
inline constexpr const char* kManifestName = "manifest.yaml";

// Addresses of the lidar's traffic (the RS-16's factory settings).
inline constexpr std::uint32_t kLidarIp = 0xC0A801C8;  // 192.168.1.200
inline constexpr std::uint32_t kHostIp = 0xC0A80166;   // 192.168.1.102

struct RunSummary {
  double duration_s = 0.0;
  std::uint64_t msop_packets = 0;
  std::uint64_t difop_packets = 0;
  std::uint64_t imu_frames = 0;
  std::uint64_t imu_reads = 0;
  std::uint64_t imu_clipped_frames = 0;
  std::uint64_t ground_truth_poses = 0;
};

// Creates out_dir if needed; files appear under their final names only when complete.
RunSummary write_run(const SimRun& run, const std::filesystem::path& out_dir);

// Pieces of write_run, usable alone.
std::uint64_t write_ground_truth(const SimRun& run, const std::filesystem::path& path);
void write_manifest(const SimRun& run, const RunSummary& summary, const std::filesystem::path& path);

}  // namespace tumble::sim
