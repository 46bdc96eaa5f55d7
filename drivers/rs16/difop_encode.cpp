#include "drivers/rs16/difop_encode.hpp"

#include <cmath>
#include <span>
#include <stdexcept>
#include <string>

#include "drivers/rs16/packet_layout.hpp"
#include "drivers/rs16/utc_time.hpp"

namespace tumble::rs16 {
namespace {

constexpr std::size_t kFovStartOffset = 32;
constexpr std::size_t kFovEndOffset = 34;

std::uint32_t encode_vertical_angle(int laser, double angle_deg) {
  const bool downward = laser < kLasers / 2;
  if (!std::isfinite(angle_deg) || (downward && angle_deg > 0.0) || (!downward && angle_deg < 0.0))
    throw std::invalid_argument("encode_difop: laser " + std::to_string(laser) + " vertical angle " +
                                std::to_string(angle_deg) + " deg must be " + (downward ? "<= 0" : ">= 0"));
  const long units = std::lround(std::abs(angle_deg) / kVerticalAngleUnitDeg);
  if (units > 0xFFFFFF)
    throw std::invalid_argument("encode_difop: laser " + std::to_string(laser) + " vertical angle " +
                                std::to_string(angle_deg) + " deg does not fit the 24-bit field");
  return static_cast<std::uint32_t>(units);
}

}  // namespace

std::array<std::uint8_t, 1248> encode_difop(const DifopData& d) {
  std::array<std::uint8_t, kPacketSize> out{};
  const std::span<std::uint8_t> b(out);
  std::copy(kDifopMagic.begin(), kDifopMagic.end(), out.begin());
  write_u16_be(b, kDifopRpmOffset, d.motor_rpm);
  write_u16_be(b, kFovStartOffset, 0);
  write_u16_be(b, kFovEndOffset, kAzimuthUnitsPerTurn);
  std::copy(d.top_firmware.begin(), d.top_firmware.end(), out.begin() + kDifopTopFirmwareOffset);
  std::copy(d.serial.begin(), d.serial.end(), out.begin() + kDifopSerialOffset);
  out[kDifopReturnModeOffset] = d.return_mode;
  if (d.utc_time_ns != 0) encode_utc_time_ns(d.utc_time_ns, b.subspan<kDifopTimeOffset, kUtcTimeSize>());
  for (int laser = 0; laser < kLasers; ++laser)
    write_u24_be(b, kDifopVerticalAnglesOffset + 3 * laser, encode_vertical_angle(laser, d.vertical_angles_deg[laser]));
  std::copy(kDifopTail.begin(), kDifopTail.end(), out.begin() + kTailOffset);
  return out;
}

}  // namespace tumble::rs16
