#include "drivers/rs16/difop_decode.hpp"

#include <algorithm>
#include <cmath>

#include "drivers/rs16/packet_layout.hpp"
#include "drivers/rs16/utc_time.hpp"

namespace tumble::rs16 {

double range_resolution_m(const std::array<std::uint8_t, 3>& top_firmware) {
  using Bytes = std::array<std::uint8_t, 3>;
  const bool old_firmware = top_firmware == Bytes{0x00, 0x00, 0x00} || top_firmware == Bytes{0xFF, 0xFF, 0xFF} ||
                            top_firmware == Bytes{0x55, 0xAA, 0x5A};
  return old_firmware ? 0.01 : 0.005;
}

PacketError decode_difop(std::span<const std::uint8_t> b, DifopInfo& out) {
  if (b.size() != kPacketSize) return PacketError::WrongSize;
  if (!bytes_equal(b, 0, kDifopMagic)) return PacketError::WrongMagic;
  if (!bytes_equal(b, kTailOffset, kDifopTail)) return PacketError::WrongTail;

  DifopData& d = out.data;
  d.motor_rpm = read_u16_be(b, kDifopRpmOffset);
  std::copy_n(b.begin() + kDifopTopFirmwareOffset, d.top_firmware.size(), d.top_firmware.begin());
  std::copy_n(b.begin() + kDifopSerialOffset, d.serial.size(), d.serial.begin());
  d.return_mode = b[kDifopReturnModeOffset];
  const auto time_ns = decode_utc_time_ns(b.subspan<kDifopTimeOffset, kUtcTimeSize>());
  out.time_valid = time_ns.has_value();
  d.utc_time_ns = time_ns.value_or(0);
  out.resolution_m = range_resolution_m(d.top_firmware);

  const auto angles = b.subspan(kDifopVerticalAnglesOffset, 3 * kLasers);
  const bool blank = std::all_of(angles.begin(), angles.end(), [](std::uint8_t v) { return v == 0x00; }) ||
                     std::all_of(angles.begin(), angles.end(), [](std::uint8_t v) { return v == 0xFF; });
  bool plausible = true;
  for (int laser = 0; laser < kLasers; ++laser) {
    const double magnitude_deg = read_u24_be(angles, 3 * laser) * kVerticalAngleUnitDeg;
    d.vertical_angles_deg[laser] = laser < kLasers / 2 ? -magnitude_deg : magnitude_deg;
    plausible = plausible && magnitude_deg <= kMaxPlausibleVerticalAngleDeg;
  }
  out.angles_calibrated = !blank && plausible;
  return PacketError::None;
}

}  // namespace tumble::rs16
