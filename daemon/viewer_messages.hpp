// The messages for viewers (tumble-view, or any LCM subscriber): the newest
// registered scan and the local map, filled on the registration thread into
// a Mailbox's reused message, so once its vectors have grown nothing is
// allocated (see bench_core_registration's BM_ViewerMessages for the cost).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>

#include "core/local_map.hpp"
#include "core/point_cloud.hpp"
#include "tumble/map_t.hpp"
#include "tumble/scan_t.hpp"

namespace tumble::daemon {

// Points of each map voxel (map.voxel_size_m) a map message carries at most.
inline constexpr std::uint32_t kViewerMapPointsPerVoxel = 4;

// `reading`: the registered scan's de-skewed, filtered points in L, with
// their weights; T_wl: its registered pose.
void fill_viewer_scan(const PointCloud& reading, const Eigen::Isometry3d& T_wl, double t_scan_start_s,
                      std::uint64_t scan_index, tumble::scan_t& scan);

void fill_viewer_map(const LocalMap& map, double t_scan_start_s, std::uint64_t scan_index, std::int32_t resets,
                     tumble::map_t& message);

}  // namespace tumble::daemon
