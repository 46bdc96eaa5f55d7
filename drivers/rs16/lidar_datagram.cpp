#include "drivers/rs16/lidar_datagram.hpp"

#include <arpa/inet.h>

#include <stdexcept>

namespace tumble::rs16 {

void validate(const SourceConfig& c) {
  if (c.msop_port == 0 || c.difop_port == 0 || c.msop_port == c.difop_port)
    throw std::invalid_argument("rs16.msop_port / rs16.difop_port = " + std::to_string(c.msop_port) + " / " +
                                std::to_string(c.difop_port) + ": must be two different ports in 1..65535");
}

std::optional<PacketKind> kind_for_port(const SourceConfig& c, std::uint16_t port) {
  if (port == c.msop_port) return PacketKind::Msop;
  if (port == c.difop_port) return PacketKind::Difop;
  return std::nullopt;
}

std::uint32_t parse_ipv4(const std::string& text) {
  in_addr address{};
  if (inet_pton(AF_INET, text.c_str(), &address) != 1)
    throw std::invalid_argument("'" + text + "' is not an IPv4 address (a.b.c.d)");
  return ntohl(address.s_addr);
}

std::string format_ipv4(std::uint32_t address) {
  return std::to_string(address >> 24) + "." + std::to_string((address >> 16) & 0xFF) + "." +
         std::to_string((address >> 8) & 0xFF) + "." + std::to_string(address & 0xFF);
}

}  // namespace tumble::rs16
