// Builds MSOP packets (used by the simulator and by round-trip tests): the
// exact inverse of the decoder for every field the packet can represent.
#pragma once

#include <array>
#include <cstdint>

namespace tumble::rs16 {

struct ChannelReturn {
  double distance_m = 0;  // 0 m = no return
  std::uint8_t reflectivity = 0;
};

struct MsopBlockData {
  double azimuth_deg = 0;
  std::array<ChannelReturn, 32> channels{};
};

struct MsopPacketData {
  std::int64_t utc_time_ns = 0;  // time of the packet's first firing
  double temperature_c = 35.0;
  std::array<MsopBlockData, 12> blocks{};
};

// Distances round to the nearest resolution step; one beyond the 16-bit
// range is sent as "no return", as the sensor cannot report it. Azimuths wrap
// into [0, 360). Throws std::invalid_argument / std::out_of_range for a
// non-positive resolution, a non-finite value or a time outside 2000..2255.
std::array<std::uint8_t, 1248> encode_msop(const MsopPacketData& p, double resolution_m = 0.005);

}  // namespace tumble::rs16
