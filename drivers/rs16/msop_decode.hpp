// Reads MSOP packets: the header, the raw fields, and the points with their
// firing times (docs/sensors.md, "RS-16: MSOP packet", "RS-16: per-point
// time and azimuth", "RS-16: geometry").
#pragma once

#include <cstdint>
#include <span>

#include "drivers/rs16/decoded_packet.hpp"
#include "drivers/rs16/decoder_stats.hpp"
#include "drivers/rs16/laser_geometry.hpp"
#include "drivers/rs16/msop_encode.hpp"
#include "drivers/rs16/packet_error.hpp"

namespace tumble::rs16 {

struct MsopHeader {
  std::int64_t utc_time_ns = 0;  // first firing, lidar clock
  double temperature_c = 0.0;
  int valid_blocks = 0;  // blocks before the first wrong flag or azimuth >= 360 deg
};

// Checks size, magic, tail, header time and the block flags.
PacketError parse_msop_header(std::span<const std::uint8_t> bytes, MsopHeader& out);

// Everything the packet says, as encode_msop takes it (its exact inverse for
// representable values). Blocks from header.valid_blocks on are left zero.
PacketError decode_msop_fields(std::span<const std::uint8_t> bytes, double resolution_m, MsopPacketData& out,
                               MsopHeader& header);

// What the point decoder needs to know about the sensor and the user's limits.
struct PointSettings {
  double resolution_m = 0.005;
  ReturnMode return_mode = ReturnMode::Strongest;
  double rpm = 600.0;
  double min_range_m = 0.4;
  double max_range_m = 200.0;
};

// Turns a packet whose header parsed into points; first_firing_host_s is the
// header time mapped to the host clock. Returns without points are counted in dropped.
void decode_msop_points(std::span<const std::uint8_t> bytes, const MsopHeader& header, double first_firing_host_s,
                        const LaserTable& lasers, const PointSettings& settings, DecodedPacket& out,
                        DroppedPoints& dropped);

}  // namespace tumble::rs16
