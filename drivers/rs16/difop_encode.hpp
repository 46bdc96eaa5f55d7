// Builds DIFOP packets (used by the simulator and by round-trip tests).
#pragma once

#include <array>
#include <cstdint>

namespace tumble::rs16 {

struct DifopData {
  std::uint16_t motor_rpm = 600;
  std::array<double, 16> vertical_angles_deg{};  // per laser, encoded at 0.0001 deg
  std::uint8_t return_mode = 1;                  // 0 dual, 1 strongest, 2 last
  std::array<std::uint8_t, 3> top_firmware{0x01, 0x02, 0x03};  // not an "old firmware" marker => 0.5 cm
  std::int64_t utc_time_ns = 0;                                // 0 = lidar clock not set (all-zero field)
  std::array<std::uint8_t, 6> serial{};
};

// The packet carries no sign: lasers 0..7 point down (angle <= 0) and 8..15 up
// (angle >= 0). Throws std::invalid_argument naming the laser when an angle
// breaks that or does not fit 24 bits, std::out_of_range for a time outside
// 2000..2255. The FOV field says the full turn.
std::array<std::uint8_t, 1248> encode_difop(const DifopData& d);

}  // namespace tumble::rs16
