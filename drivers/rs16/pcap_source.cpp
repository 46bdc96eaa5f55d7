#include "drivers/rs16/pcap_source.hpp"

#include <spdlog/spdlog.h>

#include "drivers/pcap/udp_frame.hpp"

namespace tumble::rs16 {
namespace {

bool lidar_link_type(int link_type) {
  return link_type == pcap::kLinkEthernet || link_type == pcap::kLinkLinuxSll || link_type == pcap::kLinkLinuxSll2 ||
         link_type == pcap::kLinkRawIpv4 || link_type == pcap::kLinkRaw || link_type == pcap::kDltRaw;
}

// Whole seconds and the fraction apart, so the one rounding is the final one.
double ns_to_s(std::int64_t t_ns) {
  return static_cast<double>(t_ns / 1'000'000'000) + static_cast<double>(t_ns % 1'000'000'000) * 1e-9;
}

}  // namespace

PcapSource::PcapSource(const std::string& path, const SourceConfig& config) : reader_(path), config_(config) {
  validate(config);
  if (!lidar_link_type(reader_.link_type()))
    throw pcap::Error("lidar recording " + path + " has link type " + std::to_string(reader_.link_type()) +
                      "; expected Ethernet (1), Linux cooked v1 (113) or v2 (276), or raw IPv4 (228, 101)");
}

std::optional<LidarDatagram> PcapSource::next() {
  while (const auto record = reader_.next()) {
    ++stats_.records;
    const auto udp = pcap::parse_udp_datagram(reader_.link_type(), record->bytes);
    if (!udp) {
      ++stats_.not_udp;
      continue;
    }
    const auto kind = kind_for_port(config_, udp->dst_port);
    if (!kind) {
      ++stats_.other_port;
      continue;
    }
    if (config_.source_ip && udp->src_ip != *config_.source_ip) {
      ++stats_.wrong_source;
      continue;
    }
    ++(*kind == PacketKind::Msop ? stats_.msop : stats_.difop);
    return LidarDatagram{*kind, ns_to_s(record->t_ns), udp->src_ip, udp->payload};
  }
  if (reader_.truncated() && error_.empty()) {
    error_ = "lidar recording " + reader_.path() + " is truncated or corrupt after record " +
             std::to_string(stats_.records) + " (" + reader_.error() + "); replayed what came before";
    spdlog::warn("rs16: {}", error_);
  }
  return std::nullopt;
}

}  // namespace tumble::rs16
