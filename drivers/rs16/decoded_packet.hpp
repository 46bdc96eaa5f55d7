// One MSOP packet turned into points: fixed capacity, so it can be reused or
// passed through a ring without allocating.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "core/types.hpp"
#include "drivers/rs16/firing_model.hpp"
#include "drivers/rs16/packet_layout.hpp"

namespace tumble::rs16 {

struct DecodedPacket {
  double t_s = 0.0;        // host time of the packet's first firing
  double lidar_t_s = 0.0;  // the same instant on the lidar clock (header time)
  double rpm = 600.0;      // motor speed the decoder assumed (DIFOP or default)
  ReturnMode return_mode = ReturnMode::Strongest;
  float temperature_c = 0.0f;
  int block_count = 0;  // valid blocks; the rest of the packet was cut by a wrong flag
  std::array<std::uint16_t, kBlocks> block_azimuth{};  // 0.01 deg
  // Points of block b are points[block_begin[b], block_begin[b + 1]).
  std::array<std::uint16_t, kBlocks + 1> block_begin{};
  std::array<std::uint8_t, kBlocks> block_dropped{};  // returns of block b that gave no point
  std::array<LidarPoint, kMaxPointsPerPacket> points{};

  std::span<const LidarPoint> block_points(int b) const {
    return std::span<const LidarPoint>(points).subspan(block_begin[b], block_begin[b + 1] - block_begin[b]);
  }
  std::span<const LidarPoint> all_points() const {
    return std::span<const LidarPoint>(points).first(block_begin[block_count]);
  }
};

}  // namespace tumble::rs16
