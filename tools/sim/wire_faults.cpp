#include "tools/sim/wire_faults.hpp"

#include <algorithm>
#include <bit>
#include <limits>

#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/xbus_frame.hpp"
#include "drivers/mti/xdi.hpp"
#include "drivers/rs16/difop_decode.hpp"
#include "drivers/rs16/difop_encode.hpp"
#include "drivers/rs16/packet_layout.hpp"

namespace tumble::sim {
namespace {

std::size_t block_azimuth_offset(int block) {
  return rs16::kFirstBlockOffset + rs16::kBlockSize * static_cast<std::size_t>(block) + rs16::kBlockAzimuthOffset;
}

// Xbus: preamble 0xFA, bus id 0xFF, MID, one length byte, payload, checksum.
constexpr std::size_t kXbusHeader = 4;
constexpr std::uint16_t kXdiFormatMask = 0x0003;  // 0 = float32
constexpr std::uint16_t kXdiTypeMask = 0xFFF0;

void write_nan_be(std::span<std::uint8_t> out) {
  const auto bits = std::bit_cast<std::uint32_t>(std::numeric_limits<float>::quiet_NaN());
  for (int i = 0; i < 4; ++i) out[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(bits >> (24 - 8 * i));
}

// Within one MTData2 payload: NaN into the x rate of a float32 RateOfTurn.
bool poison_payload(std::span<std::uint8_t> payload) {
  for (std::size_t at = 0; at + 3 <= payload.size();) {
    const auto id = static_cast<std::uint16_t>(payload[at] << 8 | payload[at + 1]);
    const std::size_t size = payload[at + 2];
    if (at + 3 + size > payload.size()) return false;
    if ((id & kXdiTypeMask) == mti::xdi::kRateOfTurn && (id & kXdiFormatMask) == 0 && size == 12) {
      write_nan_be(payload.subspan(at + 3, 4));
      return true;
    }
    at += 3 + size;
  }
  return false;
}

}  // namespace

bool stall_msop_azimuths(std::span<std::uint8_t> payload, std::uint16_t azimuth) {
  if (payload.size() != rs16::kPacketSize) return false;
  for (int b = 0; b < rs16::kBlocks; ++b) rs16::write_u16_be(payload, block_azimuth_offset(b), azimuth);
  return true;
}

bool recalibrate_difop(std::span<std::uint8_t> payload) {
  rs16::DifopInfo info;
  if (rs16::decode_difop(payload, info) != rs16::PacketError::None || !info.angles_calibrated) return false;
  for (double& angle : info.data.vertical_angles_deg) angle *= kRecalibratedAngleScale;
  const auto bytes = rs16::encode_difop(info.data);
  std::copy(bytes.begin(), bytes.end(), payload.begin());
  return true;
}

std::uint16_t last_msop_azimuth(std::span<const std::uint8_t> payload) {
  return rs16::read_u16_be(payload, block_azimuth_offset(rs16::kBlocks - 1));
}

std::uint64_t poison_rate_of_turn(std::span<std::uint8_t> stream, const std::function<bool()>& pick) {
  std::uint64_t poisoned = 0;
  for (std::size_t p = 0; p + kXbusHeader < stream.size(); ++p) {
    if (stream[p] != mti::kPreamble || stream[p + 1] != mti::kBusIdMaster || stream[p + 2] != mti::mid::kMtData2)
      continue;
    const std::size_t length = stream[p + 3];
    if (length == 0xFF || p + kXbusHeader + length + 1 > stream.size()) continue;
    if (!pick() || !poison_payload(stream.subspan(p + kXbusHeader, length))) continue;
    stream[p + kXbusHeader + length] =
        mti::xbus_checksum(mti::kBusIdMaster, mti::mid::kMtData2, stream.subspan(p + 3, length + 1));
    ++poisoned;
    p += kXbusHeader + length;
  }
  return poisoned;
}

}  // namespace tumble::sim
