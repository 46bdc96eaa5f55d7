// What a lidar source (pcap replay or live UDP) hands on: one MSOP or DIFOP
// payload and when it reached the host.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace tumble::rs16 {

enum class PacketKind : std::uint8_t { Msop, Difop };

struct LidarDatagram {
  PacketKind kind = PacketKind::Msop;
  double arrival_s = 0.0;  // host clock (CLOCK_REALTIME)
  std::uint32_t source_ip = 0;  // host byte order
  std::span<const std::uint8_t> payload;  // valid until the source's next datagram
};

struct SourceConfig {
  std::uint16_t msop_port = 6699;
  std::uint16_t difop_port = 7788;
  std::optional<std::uint32_t> source_ip;  // only this sender (host byte order); others dropped and counted
};

// Throws std::invalid_argument when the ports are 0 or equal.
void validate(const SourceConfig& config);

// Which packet a UDP destination port carries, if any.
std::optional<PacketKind> kind_for_port(const SourceConfig& config, std::uint16_t port);

// "a.b.c.d" <-> host-order address; parse throws std::invalid_argument naming the text.
std::uint32_t parse_ipv4(const std::string& text);
std::string format_ipv4(std::uint32_t address);

}  // namespace tumble::rs16
