#include "drivers/rs16/msop_decode.hpp"

#include <cmath>
#include <numbers>

#include "drivers/rs16/firing_model.hpp"
#include "drivers/rs16/utc_time.hpp"

namespace tumble::rs16 {
namespace {

constexpr double kRadPerAzimuthUnit = std::numbers::pi / 18000.0;
constexpr ChannelTiming kSingleTiming = channel_timing(ReturnMode::Strongest);
constexpr ChannelTiming kDualTiming = channel_timing(ReturnMode::Dual);

// Dual return: both returns of a laser come from one firing; emit them
// together so the points stay in firing-time order.
constexpr std::array<std::uint8_t, kChannelsPerBlock> channel_order(ReturnMode mode) {
  std::array<std::uint8_t, kChannelsPerBlock> order{};
  for (int i = 0; i < kChannelsPerBlock; ++i)
    order[i] = static_cast<std::uint8_t>(mode == ReturnMode::Dual ? (i % 2) * kLasers + i / 2 : i);
  return order;
}
constexpr auto kSingleOrder = channel_order(ReturnMode::Strongest);
constexpr auto kDualOrder = channel_order(ReturnMode::Dual);

std::size_t block_offset(int b) { return kFirstBlockOffset + kBlockSize * static_cast<std::size_t>(b); }

std::uint16_t block_azimuth(std::span<const std::uint8_t> bytes, int b) {
  return read_u16_be(bytes, block_offset(b) + kBlockAzimuthOffset);
}

double decode_temperature_c(std::uint8_t b38, std::uint8_t b39) {
  const int value = ((b39 & 0x7F) << 5) + (b38 >> 3);
  return ((b39 & 0x80) != 0 ? -value : value) * 0.0625;
}

}  // namespace

PacketError parse_msop_header(std::span<const std::uint8_t> bytes, MsopHeader& out) {
  if (bytes.size() != kPacketSize) return PacketError::WrongSize;
  if (!bytes_equal(bytes, 0, kMsopMagic)) return PacketError::WrongMagic;
  if (!bytes_equal(bytes, kTailOffset, kMsopTail)) return PacketError::WrongTail;
  const auto time_ns = decode_utc_time_ns(bytes.subspan<kMsopTimeOffset, kUtcTimeSize>());
  if (!time_ns) return PacketError::BadTimestamp;
  out.utc_time_ns = *time_ns;
  out.temperature_c = decode_temperature_c(bytes[kMsopTemperatureOffset], bytes[kMsopTemperatureOffset + 1]);
  out.valid_blocks = 0;
  while (out.valid_blocks < kBlocks && bytes_equal(bytes, block_offset(out.valid_blocks), kBlockFlag) &&
         block_azimuth(bytes, out.valid_blocks) < kAzimuthUnitsPerTurn)
    ++out.valid_blocks;
  return out.valid_blocks == 0 ? PacketError::NoValidBlocks : PacketError::None;
}

PacketError decode_msop_fields(std::span<const std::uint8_t> bytes, double resolution_m, MsopPacketData& out,
                               MsopHeader& header) {
  const PacketError e = parse_msop_header(bytes, header);
  if (e != PacketError::None) return e;
  out = MsopPacketData{};
  out.utc_time_ns = header.utc_time_ns;
  out.temperature_c = header.temperature_c;
  for (int b = 0; b < header.valid_blocks; ++b) {
    out.blocks[b].azimuth_deg = block_azimuth(bytes, b) * 0.01;
    for (int c = 0; c < kChannelsPerBlock; ++c) {
      const std::size_t at = block_offset(b) + kBlockChannelsOffset + kChannelSize * c;
      out.blocks[b].channels[c] = {read_u16_be(bytes, at) * resolution_m, bytes[at + 2]};
    }
  }
  return PacketError::None;
}

void decode_msop_points(std::span<const std::uint8_t> bytes, const MsopHeader& header, double first_firing_host_s,
                        const LaserTable& lasers, const PointSettings& s, DecodedPacket& out,
                        DroppedPoints& dropped) {
  const bool dual = s.return_mode == ReturnMode::Dual;
  const ChannelTiming& timing = dual ? kDualTiming : kSingleTiming;
  const auto& order = dual ? kDualOrder : kSingleOrder;
  const double nominal_step = nominal_block_step(s.rpm, s.return_mode);
  const double block_period = block_period_s(s.return_mode);

  out.t_s = first_firing_host_s;
  out.lidar_t_s = static_cast<double>(header.utc_time_ns) * 1e-9;
  out.rpm = s.rpm;
  out.return_mode = s.return_mode;
  out.temperature_c = static_cast<float>(header.temperature_c);
  out.block_count = header.valid_blocks;
  for (int b = 0; b < header.valid_blocks; ++b) out.block_azimuth[b] = block_azimuth(bytes, b);

  std::uint16_t n = 0;
  for (int b = 0; b < header.valid_blocks; ++b) {
    out.block_begin[b] = n;
    const std::uint16_t azimuth = out.block_azimuth[b];
    // The last block has no successor: it turns like the one before it.
    double step = nominal_step;
    if (b + 1 < header.valid_blocks)
      step = interpolation_step(azimuth, out.block_azimuth[b + 1], nominal_step);
    else if (b > 0)
      step = interpolation_step(out.block_azimuth[b - 1], azimuth, nominal_step);
    const double azimuth_rad = azimuth * kRadPerAzimuthUnit;
    const double cos_block = std::cos(azimuth_rad), sin_block = std::sin(azimuth_rad);
    const double step_rad = step * kRadPerAzimuthUnit;
    const double block_t_s = first_firing_host_s + block_period * b;
    const std::size_t channels_at = block_offset(b) + kBlockChannelsOffset;
    int block_dropped = 0;
    for (const std::uint8_t c : order) {
      const std::size_t at = channels_at + kChannelSize * c;
      const std::uint16_t raw = read_u16_be(bytes, at);
      const double distance_m = raw * s.resolution_m;
      if (raw == 0 || distance_m < s.min_range_m || distance_m > s.max_range_m) {
        if (raw == 0)
          ++dropped.zero_range;
        else if (distance_m < s.min_range_m)
          ++dropped.too_near;
        else
          ++dropped.too_far;
        ++block_dropped;
        continue;
      }
      // The turn since the block's azimuth is below ~1 deg: a short series for
      // its sine and cosine is exact to 1e-11 and saves two libm calls per point.
      const double turn = step_rad * timing.azimuth_fraction[c];
      const double turn2 = turn * turn;
      const double sin_turn = turn * (1.0 - turn2 / 6.0);
      const double cos_turn = 1.0 - turn2 / 2.0 + turn2 * turn2 / 24.0;
      const double cos_az = cos_block * cos_turn - sin_block * sin_turn;
      const double sin_az = sin_block * cos_turn + cos_block * sin_turn;
      const int laser = c % kLasers;
      const PointXyz p = to_cartesian(distance_m, lasers.cos_vertical[laser], lasers.sin_vertical[laser], cos_az, sin_az);
      double azimuth_deg = (azimuth + step * timing.azimuth_fraction[c]) * 0.01;
      if (azimuth_deg >= 360.0) azimuth_deg -= 360.0;

      LidarPoint& point = out.points[n++];
      point.t_s = block_t_s + timing.offset_s[c];
      point.x_m = static_cast<float>(p.x_m);
      point.y_m = static_cast<float>(p.y_m);
      point.z_m = static_cast<float>(p.z_m);
      point.intensity = bytes[at + 2];
      const auto azimuth_f = static_cast<float>(azimuth_deg);
      point.azimuth_deg = azimuth_f < 360.0f ? azimuth_f : 0.0f;
      point.laser = static_cast<std::uint8_t>(laser);
      point.return_index = static_cast<std::uint8_t>(dual && c >= kLasers ? 1 : 0);
    }
    out.block_dropped[b] = static_cast<std::uint8_t>(block_dropped);
  }
  out.block_begin[header.valid_blocks] = n;
}

}  // namespace tumble::rs16
