#include "drivers/pcap/udp_frame.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <pcap/dlt.h>

#include "drivers/pcap/pcap_file.hpp"

static_assert(tumble::pcap::kDltRaw == DLT_RAW, "libpcap numbers DLT_RAW differently here");

namespace tumble::pcap {
namespace {

constexpr std::uint16_t kEtherTypeIpv4 = 0x0800;
constexpr std::uint16_t kEtherTypeVlan = 0x8100;
constexpr std::uint16_t kEtherTypeQinQ = 0x88A8;
constexpr std::size_t kEthernetHeader = 14;
constexpr std::size_t kVlanTag = 4;
constexpr std::size_t kSllHeader = 16;
constexpr std::size_t kSllProtocolOffset = 14;
constexpr std::size_t kSll2Header = 20;
constexpr std::size_t kIpv4MinHeader = 20;
constexpr std::size_t kUdpHeader = 8;
constexpr std::uint8_t kProtocolUdp = 17;
constexpr std::size_t kMaxUdpPayload = 65535 - kIpv4MinHeader - kUdpHeader;

std::uint16_t u16(std::span<const std::uint8_t> b, std::size_t at) {
  return static_cast<std::uint16_t>((b[at] << 8) | b[at + 1]);
}

std::uint32_t u32(std::span<const std::uint8_t> b, std::size_t at) {
  return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) | (std::uint32_t{b[at + 2]} << 8) | b[at + 3];
}

// Where the IPv4 header starts, if the link layer says IPv4 follows.
std::optional<std::size_t> ipv4_start(int link_type, std::span<const std::uint8_t> f) {
  switch (link_type) {
    case kLinkEthernet: {
      std::size_t at = 12;  // EtherType after the two MAC addresses
      if (f.size() < at + 2) return std::nullopt;
      for (int tags = 0; tags < 2 && (u16(f, at) == kEtherTypeVlan || u16(f, at) == kEtherTypeQinQ); ++tags) {
        at += kVlanTag;
        if (f.size() < at + 2) return std::nullopt;
      }
      if (u16(f, at) != kEtherTypeIpv4) return std::nullopt;
      return at + 2;
    }
    case kLinkLinuxSll:
      if (f.size() < kSllHeader || u16(f, kSllProtocolOffset) != kEtherTypeIpv4) return std::nullopt;
      return kSllHeader;
    case kLinkLinuxSll2:
      if (f.size() < kSll2Header || u16(f, 0) != kEtherTypeIpv4) return std::nullopt;
      return kSll2Header;
    case kLinkRawIpv4:
    case kLinkRaw:
    case kDltRaw:
      return 0;
    default:
      return std::nullopt;
  }
}

void put_u16(std::vector<std::uint8_t>& b, std::size_t at, std::uint16_t v) {
  b[at] = static_cast<std::uint8_t>(v >> 8);
  b[at + 1] = static_cast<std::uint8_t>(v & 0xFF);
}

void put_u32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<std::uint8_t>(v >> (24 - 8 * i));
}

}  // namespace

std::optional<UdpDatagram> parse_udp_datagram(int link_type, std::span<const std::uint8_t> frame) {
  const auto start = ipv4_start(link_type, frame);
  if (!start) return std::nullopt;
  const auto ip = frame.subspan(*start);
  if (ip.size() < kIpv4MinHeader || (ip[0] >> 4) != 4) return std::nullopt;
  const std::size_t header_length = std::size_t{ip[0] & 0x0Fu} * 4;
  const std::size_t total_length = u16(ip, 2);
  const bool fragment = (u16(ip, 6) & 0x3FFF) != 0;  // more-fragments flag or an offset
  if (header_length < kIpv4MinHeader || total_length < header_length + kUdpHeader || fragment ||
      ip[9] != kProtocolUdp || ip.size() < header_length + kUdpHeader)
    return std::nullopt;
  const auto udp = ip.subspan(header_length);
  const std::size_t udp_length = u16(udp, 4);
  if (udp_length < kUdpHeader) return std::nullopt;
  // Trailing link padding is not payload; a capture cut short leaves less.
  std::size_t payload_length = std::min(udp_length, total_length - header_length) - kUdpHeader;
  payload_length = std::min(payload_length, udp.size() - kUdpHeader);
  return UdpDatagram{u32(ip, 12), u16(udp, 0), u16(udp, 2), udp.subspan(kUdpHeader, payload_length)};
}

void make_udp_ethernet_frame(std::uint32_t src_ip, std::uint32_t dst_ip, std::uint16_t src_port,
                             std::uint16_t dst_port, std::span<const std::uint8_t> payload,
                             std::vector<std::uint8_t>& f) {
  if (payload.size() > kMaxUdpPayload)
    throw std::invalid_argument("UDP payload of " + std::to_string(payload.size()) + " bytes exceeds " +
                                std::to_string(kMaxUdpPayload));
  const std::size_t ip_length = kIpv4MinHeader + kUdpHeader + payload.size();
  f.assign(kEthernetHeader + ip_length, 0);
  for (std::size_t i = 0; i < 6; ++i) f[i] = 0xFF;
  f[6] = 0x02;  // locally administered, unicast
  f[7] = 0x00;
  put_u32(f, 8, src_ip);
  put_u16(f, 12, kEtherTypeIpv4);

  const std::size_t ip = kEthernetHeader;
  f[ip] = 0x45;  // IPv4, 20-byte header
  put_u16(f, ip + 2, static_cast<std::uint16_t>(ip_length));
  put_u16(f, ip + 6, 0x4000);  // don't fragment
  f[ip + 8] = 64;
  f[ip + 9] = kProtocolUdp;
  put_u32(f, ip + 12, src_ip);
  put_u32(f, ip + 16, dst_ip);
  std::uint32_t sum = 0;
  for (std::size_t i = 0; i < kIpv4MinHeader; i += 2) sum += u16(f, ip + i);
  while (sum > 0xFFFF) sum = (sum & 0xFFFF) + (sum >> 16);
  put_u16(f, ip + 10, static_cast<std::uint16_t>(~sum & 0xFFFF));

  const std::size_t udp = ip + kIpv4MinHeader;
  put_u16(f, udp, src_port);
  put_u16(f, udp + 2, dst_port);
  put_u16(f, udp + 4, static_cast<std::uint16_t>(kUdpHeader + payload.size()));
  std::copy(payload.begin(), payload.end(), f.begin() + static_cast<std::ptrdiff_t>(udp + kUdpHeader));
}

std::vector<std::uint8_t> make_udp_ethernet_frame(std::uint32_t src_ip, std::uint32_t dst_ip, std::uint16_t src_port,
                                                  std::uint16_t dst_port, std::span<const std::uint8_t> payload) {
  std::vector<std::uint8_t> frame;
  make_udp_ethernet_frame(src_ip, dst_ip, src_port, dst_port, payload, frame);
  return frame;
}

}  // namespace tumble::pcap
