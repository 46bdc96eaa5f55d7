// Replays a pcap/pcapng recording of the lidar's UDP traffic: MSOP and DIFOP
// payloads with their recorded arrival times, everything else counted and
// skipped.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "drivers/pcap/pcap_file.hpp"
#include "drivers/rs16/lidar_datagram.hpp"

namespace tumble::rs16 {

struct PcapSourceStats {
  std::uint64_t records = 0;
  std::uint64_t msop = 0;
  std::uint64_t difop = 0;
  std::uint64_t not_udp = 0;       // other protocols, IP fragments, cut-off headers
  std::uint64_t other_port = 0;    // UDP to neither lidar port
  std::uint64_t wrong_source = 0;  // lidar ports, but not from the expected sender
};

class PcapSource {
 public:
  // Throws pcap::Error naming the file when it cannot be read or its link type
  // cannot carry the lidar's traffic.
  PcapSource(const std::string& path, const SourceConfig& config);

  // The next lidar datagram (payload valid until the next call), or nullopt at
  // the end of the recording.
  std::optional<LidarDatagram> next();

  const PcapSourceStats& stats() const { return stats_; }
  // True when the recording ended in a truncated or corrupt record; error()
  // then says where, in a message fit for the user.
  bool truncated() const { return !error_.empty(); }
  const std::string& error() const { return error_; }

 private:
  pcap::Reader reader_;
  SourceConfig config_;
  PcapSourceStats stats_;
  std::string error_;
};

}  // namespace tumble::rs16
