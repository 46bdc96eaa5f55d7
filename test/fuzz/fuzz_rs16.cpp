// Fuzzes RS-16 MSOP/DIFOP decoding and scan assembly. The input is either a
// classic pcap (as the fixture seed is): its first records (enough to cross a
// scan split; more only slow the fuzzer down) go through the UDP framing
// parser and the driver; or a list of datagrams, each introduced by a
// selector byte:
//   bit 0  DIFOP instead of MSOP
//   bit 1  frame it: pad or cut the next bytes to a packet after the right
//          magic, with the right tail, so random bytes reach the block, time
//          and angle code; else a 2-byte big-endian length and raw bytes
//   bit 2  arrival time jumps back a second (exercises clock resets and gaps)
//   bit 3  framed MSOP: keep the raw header time instead of a valid, steadily
//          advancing one
//   bit 4  framed MSOP: keep the raw block flags instead of FF EE
// The first input byte also picks the decoder and scan configuration. The
// seeds include packets duplicated, swapped and late after their scan closed.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include <spdlog/spdlog.h>

#include "drivers/pcap/udp_frame.hpp"
#include "drivers/rs16/difop_decode.hpp"
#include "drivers/rs16/driver.hpp"
#include "drivers/rs16/msop_decode.hpp"
#include "drivers/rs16/packet_layout.hpp"
#include "drivers/rs16/utc_time.hpp"

namespace {

using namespace tumble::rs16;

std::uint32_t le32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) | (std::uint32_t{p[3]} << 24);
}
std::uint32_t be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
}

DriverConfig config_from(std::uint8_t selector) {
  DriverConfig c;
  c.decoder.clock = (selector & 0x10) != 0 ? ClockMode::Free : ClockMode::Synced;
  c.decoder.wait_for_difop = (selector & 0x20) != 0;
  c.scans.split_azimuth_deg = (selector & 0xC0) * 1.0;
  c.scans.min_scan_coverage = (selector & 0x0F) / 15.0;
  return c;
}

// The field-level decoder is the encoder's exact inverse: check it on whatever decodes.
void check_fields_round_trip(std::span<const std::uint8_t> payload) {
  MsopPacketData fields;
  MsopHeader header;
  if (decode_msop_fields(payload, 0.005, fields, header) != PacketError::None) return;
  if (header.valid_blocks != kBlocks) return;
  const auto again = encode_msop(fields, 0.005);
  MsopPacketData back;
  MsopHeader back_header;
  if (decode_msop_fields(again, 0.005, back, back_header) != PacketError::None) __builtin_trap();
  for (int b = 0; b < kBlocks; ++b)
    for (int c = 0; c < kChannelsPerBlock; ++c)
      if (back.blocks[b].channels[c].distance_m != fields.blocks[b].channels[c].distance_m) __builtin_trap();
}

constexpr int kMaxPcapRecords = 48;

void run_pcap(const std::uint8_t* data, std::size_t size) {
  const std::uint32_t magic = le32(data);
  const bool little = magic == 0xA1B2C3D4 || magic == 0xA1B23C4D;
  const bool nano = magic == 0xA1B23C4D || magic == 0x4D3CB2A1;
  auto u32 = [&](const std::uint8_t* p) { return little ? le32(p) : be32(p); };
  const int link_type = static_cast<int>(u32(data + 20) & 0x0FFFFFFF);
  Driver driver(config_from(data[size - 1]), [](tumble::Scan&, const ScanReport&) {});
  const SourceConfig ports;
  std::size_t at = 24;
  for (int record = 0; record < kMaxPcapRecords && at + 16 <= size; ++record) {
    const double arrival_s = u32(data + at) + u32(data + at + 4) * (nano ? 1e-9 : 1e-6);
    const std::size_t length = u32(data + at + 8);
    at += 16;
    if (length > size - at) break;
    const auto udp = tumble::pcap::parse_udp_datagram(link_type, {data + at, length});
    at += length;
    if (!udp) continue;
    const auto kind = kind_for_port(ports, udp->dst_port);
    if (!kind) continue;
    driver.on_datagram({*kind, arrival_s, udp->src_ip, udp->payload});
    if (*kind == PacketKind::Msop) check_fields_round_trip(udp->payload);
  }
}

void run_datagrams(const std::uint8_t* data, std::size_t size) {
  Driver driver(config_from(data[0]), [](tumble::Scan&, const ScanReport&) {});
  std::vector<std::uint8_t> packet(kPacketSize);
  double arrival_s = 1.7e9;
  std::int64_t header_ns = 1'704'067'200'000'000'000;
  std::size_t at = 1;
  while (at < size) {
    const std::uint8_t selector = data[at++];
    const PacketKind kind = (selector & 1) != 0 ? PacketKind::Difop : PacketKind::Msop;
    arrival_s += (selector & 4) != 0 ? -1.0 : 1.332e-3;
    std::span<const std::uint8_t> payload;
    if ((selector & 2) != 0) {
      const std::size_t body = std::min(size - at, kPacketSize - 10);
      std::fill(packet.begin(), packet.end(), 0);
      const auto& magic = kind == PacketKind::Difop ? kDifopMagic : kMsopMagic;
      const auto& tail = kind == PacketKind::Difop ? kDifopTail : kMsopTail;
      std::copy(magic.begin(), magic.end(), packet.begin());
      std::memcpy(packet.data() + magic.size(), data + at, body);
      std::copy(tail.begin(), tail.end(), packet.begin() + kTailOffset);
      if (kind == PacketKind::Msop && (selector & 8) == 0) {
        header_ns += 1'332'000;
        encode_utc_time_ns(header_ns, std::span(packet).subspan<kMsopTimeOffset, kUtcTimeSize>());
      }
      if (kind == PacketKind::Msop && (selector & 16) == 0) {
        for (int b = 0; b < kBlocks; ++b)
          std::copy(kBlockFlag.begin(), kBlockFlag.end(), packet.begin() + kFirstBlockOffset + kBlockSize * b);
      }
      at += body;
      payload = packet;
    } else {
      if (size - at < 2) break;
      const std::size_t length = std::min<std::size_t>((std::size_t{data[at]} << 8) | data[at + 1], size - at - 2);
      at += 2;
      payload = {data + at, length};
      at += length;
    }
    driver.on_datagram({kind, arrival_s, 0, payload});
    if (kind == PacketKind::Msop) check_fields_round_trip(payload);
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spdlog::set_level(spdlog::level::off);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint32_t magic = size >= 24 ? le32(data) : 0;
  if (magic == 0xA1B2C3D4 || magic == 0xD4C3B2A1 || magic == 0xA1B23C4D || magic == 0x4D3CB2A1)
    run_pcap(data, size);
  else
    run_datagrams(data, size);
  return 0;
}
