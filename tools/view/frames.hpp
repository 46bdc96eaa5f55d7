// tumbled's LCM messages as the frames the page reads: JSON text for the
// pose, status and link, binary for points (a 16-byte header, then one
// float32 array per field, little-endian as every browser's typed arrays).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "tools/view/outbound_queue.hpp"
#include "tumble/map_t.hpp"
#include "tumble/odometry_t.hpp"
#include "tumble/registration_t.hpp"
#include "tumble/scan_t.hpp"
#include "tumble/status_t.hpp"

namespace tumble::view {

// Points sent to a browser per scan and per map at most: more are strided.
inline constexpr std::size_t kMaxScanPoints = 30000;
inline constexpr std::size_t kMaxMapPoints = 100000;

// What the web thread tells browsers about the LCM side once a second.
struct LinkReport {
  std::string lcm_url;
  std::string channel_prefix;
  std::uint64_t messages = 0;     // received since start, every channel
  double since_last_s = -1;       // since the newest message; negative: none yet
  std::size_t browsers = 0;
};

Frame status_frame(const tumble::status_t& status);
Frame pose_frame(const tumble::registration_t& pose);
Frame odometry_frame(const tumble::odometry_t& odometry);
// "SCAN", n, scan_index, stride (uint32), then x, y, z, sigma_s_m, weight, ring (float32 [n] each).
Frame scan_frame(const tumble::scan_t& scan);
// "MAP_", n, map_points (in the whole map), stride (uint32), then x, y, z (float32 [n] each).
Frame map_frame(const tumble::map_t& map);
Frame link_frame(const LinkReport& link);
// The trajectory so far (x, y, z of each registered pose), for a browser that joins.
Frame history_frame(std::span<const float> xyz);

std::string json_string(const std::string& text);  // quoted and escaped

}  // namespace tumble::view
