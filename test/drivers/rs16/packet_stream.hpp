// Synthetic MSOP packets of a lidar turning at a steady speed, for tests.
#pragma once

#include <cmath>
#include <cstdint>

#include "drivers/rs16/firing_model.hpp"
#include "drivers/rs16/msop_encode.hpp"

namespace tumble::rs16::test {

struct StreamSpec {
  double rpm = 600.0;
  double start_azimuth_deg = 0.0;
  std::int64_t start_ns = 1'704'067'200'000'000'000;  // 2024-01-01T00:00:00Z
  double distance_m = 10.0;
  ReturnMode mode = ReturnMode::Strongest;
};

inline double block_step_deg(const StreamSpec& s) { return s.rpm * 6.0 * block_period_s(s.mode); }

// Packet number index of the stream: every channel returns distance_m with
// reflectivity = channel number.
inline MsopPacketData stream_packet(const StreamSpec& s, std::int64_t index) {
  MsopPacketData p;
  p.utc_time_ns = s.start_ns + std::llround(index * packet_duration_s(s.mode) * 1e9);
  for (int b = 0; b < 12; ++b) {
    p.blocks[b].azimuth_deg = std::fmod(s.start_azimuth_deg + block_step_deg(s) * (index * 12 + b), 360.0);
    for (int c = 0; c < 32; ++c) p.blocks[b].channels[c] = {s.distance_m, static_cast<std::uint8_t>(c)};
  }
  return p;
}

}  // namespace tumble::rs16::test
