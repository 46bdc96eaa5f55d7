// Reads a DIFOP packet: the device settings the point decoder depends on.
#pragma once

#include <cstdint>
#include <span>

#include "drivers/rs16/difop_encode.hpp"
#include "drivers/rs16/packet_error.hpp"

namespace tumble::rs16 {

// Beyond this a "calibrated" vertical angle is corrupt (the RS-16 spans +-15 deg).
inline constexpr double kMaxPlausibleVerticalAngleDeg = 25.0;

struct DifopInfo {
  DifopData data;                 // vertical angles at the full 0.0001 deg, lasers 0..7 negative
  bool angles_calibrated = false;  // false: all 0x00 / all 0xFF, or implausible; do not use data.vertical_angles_deg
  bool time_valid = false;         // false: data.utc_time_ns is 0
  double resolution_m = 0.005;     // range unit the MSOP packets use
};

// Fills out and returns PacketError::None, or returns why the packet is not a DIFOP.
PacketError decode_difop(std::span<const std::uint8_t> bytes, DifopInfo& out);

// 1 cm for the older top-board firmware (00 00 00, FF FF FF or 55 AA 5A), else 0.5 cm.
double range_resolution_m(const std::array<std::uint8_t, 3>& top_firmware);

}  // namespace tumble::rs16
