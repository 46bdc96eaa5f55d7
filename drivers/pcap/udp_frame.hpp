// UDP datagrams inside captured link-layer frames: reading them out of the
// link types tcpdump records lidar traffic with, and building Ethernet frames
// to write lidar recordings.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace tumble::pcap {

// libpcap reports a LINKTYPE_RAW (101) file as DLT_RAW, 12 on Linux; use it to
// write such a file too.
inline constexpr int kDltRaw = 12;

struct UdpDatagram {
  std::uint32_t src_ip;  // host byte order
  std::uint16_t src_port, dst_port;
  std::span<const std::uint8_t> payload;  // points into the frame; shorter than sent when the capture cut it
};

// Ethernet (incl. 802.1Q/802.1ad tags), Linux cooked v1/v2, raw IPv4 (and raw
// IP carrying IPv4, as kLinkRaw or kDltRaw). nullopt for anything else: other link types, non-IPv4,
// non-UDP, IP fragments, headers cut short (counted by the caller).
std::optional<UdpDatagram> parse_udp_datagram(int link_type, std::span<const std::uint8_t> frame);

// An Ethernet+IPv4+UDP frame carrying payload (for writing lidar pcaps):
// broadcast destination MAC, a locally administered source MAC made from
// src_ip, TTL 64, don't-fragment, UDP checksum 0 (none, as IPv4 allows).
// Throws std::invalid_argument when the payload exceeds a UDP datagram.
std::vector<std::uint8_t> make_udp_ethernet_frame(std::uint32_t src_ip, std::uint32_t dst_ip, std::uint16_t src_port,
                                                  std::uint16_t dst_port, std::span<const std::uint8_t> payload);
// The same into a caller's buffer, reusing its capacity.
void make_udp_ethernet_frame(std::uint32_t src_ip, std::uint32_t dst_ip, std::uint16_t src_port,
                             std::uint16_t dst_port, std::span<const std::uint8_t> payload,
                             std::vector<std::uint8_t>& frame);

}  // namespace tumble::pcap
