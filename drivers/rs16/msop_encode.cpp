#include "drivers/rs16/msop_encode.hpp"

#include <cmath>
#include <span>
#include <stdexcept>
#include <string>

#include "drivers/rs16/packet_layout.hpp"
#include "drivers/rs16/utc_time.hpp"

namespace tumble::rs16 {
namespace {

constexpr double kTemperatureUnit_c = 0.0625;
constexpr long kMaxTemperatureValue = (0x7F << 5) | 0x1F;

[[noreturn]] void throw_not_finite(const std::string& what) {
  throw std::invalid_argument("encode_msop: " + what + " is not finite");
}

std::uint16_t encode_azimuth(double azimuth_deg) {
  long units = std::lround(azimuth_deg * 100.0) % kAzimuthUnitsPerTurn;
  if (units < 0) units += kAzimuthUnitsPerTurn;
  return static_cast<std::uint16_t>(units);
}

}  // namespace

std::array<std::uint8_t, 1248> encode_msop(const MsopPacketData& p, double resolution_m) {
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m))
    throw std::invalid_argument("encode_msop: resolution_m must be positive, got " + std::to_string(resolution_m));
  if (!std::isfinite(p.temperature_c)) throw_not_finite("temperature_c");
  std::array<std::uint8_t, kPacketSize> out{};
  const std::span<std::uint8_t> b(out);
  std::copy(kMsopMagic.begin(), kMsopMagic.end(), out.begin());
  encode_utc_time_ns(p.utc_time_ns, b.subspan<kMsopTimeOffset, kUtcTimeSize>());
  out[kMsopLidarTypeOffset] = kLidarTypeRs16;

  const long temperature = std::min(std::lround(std::abs(p.temperature_c) / kTemperatureUnit_c), kMaxTemperatureValue);
  out[kMsopTemperatureOffset] = static_cast<std::uint8_t>((temperature & 0x1F) << 3);
  out[kMsopTemperatureOffset + 1] =
      static_cast<std::uint8_t>(((temperature >> 5) & 0x7F) | (p.temperature_c < 0.0 ? 0x80 : 0x00));

  for (int blk = 0; blk < kBlocks; ++blk) {
    const MsopBlockData& block = p.blocks[blk];
    const std::size_t base = kFirstBlockOffset + kBlockSize * blk;
    if (!std::isfinite(block.azimuth_deg)) throw_not_finite("block " + std::to_string(blk) + " azimuth_deg");
    out[base] = kBlockFlag[0];
    out[base + 1] = kBlockFlag[1];
    write_u16_be(b, base + kBlockAzimuthOffset, encode_azimuth(block.azimuth_deg));
    for (int c = 0; c < kChannelsPerBlock; ++c) {
      const ChannelReturn& r = block.channels[c];
      if (!std::isfinite(r.distance_m))
        throw_not_finite("block " + std::to_string(blk) + " channel " + std::to_string(c) + " distance_m");
      const long raw = r.distance_m > 0.0 ? std::lround(r.distance_m / resolution_m) : 0;
      const std::size_t at = base + kBlockChannelsOffset + kChannelSize * c;
      write_u16_be(b, at, raw > 0xFFFF ? 0 : static_cast<std::uint16_t>(raw));
      out[at + 2] = r.reflectivity;
    }
  }
  std::copy(kMsopTail.begin(), kMsopTail.end(), out.begin() + kTailOffset);
  return out;
}

}  // namespace tumble::rs16
