// Writes lidar datagrams as a standard Ethernet pcap, as tcpdump would have
// captured them (for `--record` and the simulator); PcapSource replays it.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "drivers/pcap/pcap_file.hpp"
#include "drivers/rs16/lidar_datagram.hpp"

namespace tumble::rs16 {

struct RecordingAddresses {
  std::uint32_t lidar_ip = 0xC0A801C8;  // 192.168.1.200, the RS-16's factory address
  std::uint32_t host_ip = 0xC0A80166;   // 192.168.1.102, its factory destination
  std::uint16_t msop_port = 6699;       // the lidar sends from and to the same port
  std::uint16_t difop_port = 7788;
};

class RecordingWriter {
 public:
  // Creates (truncates) path; throws pcap::Error naming it when it cannot.
  RecordingWriter(const std::string& path, const RecordingAddresses& addresses = {});

  // One datagram that arrived at arrival_t_ns (CLOCK_REALTIME). Reuses one
  // frame buffer: no allocation per datagram once it has grown.
  void write(std::int64_t arrival_t_ns, PacketKind kind, std::span<const std::uint8_t> payload);
  // The same, from the given sender (host byte order) instead of lidar_ip.
  void write_from(std::uint32_t source_ip, std::int64_t arrival_t_ns, PacketKind kind,
                  std::span<const std::uint8_t> payload);
  void flush() { writer_.flush(); }
  void close() { writer_.close(); }
  // The file itself: its size, errors and sync.
  pcap::Writer& file() { return writer_; }

 private:
  pcap::Writer writer_;
  RecordingAddresses addresses_;
  std::vector<std::uint8_t> frame_;
};

}  // namespace tumble::rs16
