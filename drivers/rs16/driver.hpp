// The RS-16 driver on one thread: datagrams in (from PcapSource or UdpSource),
// scans out. Where decoding and scan assembly run on different threads, use
// Decoder and ScanAssembler directly with a ring of DecodedPacket between them.
#pragma once

#include "drivers/rs16/decoded_packet.hpp"
#include "drivers/rs16/decoder.hpp"
#include "drivers/rs16/decoder_stats.hpp"
#include "drivers/rs16/lidar_datagram.hpp"
#include "drivers/rs16/scan_assembler.hpp"

namespace tumble::rs16 {

struct DriverConfig {
  DecoderConfig decoder;
  ScanAssemblerConfig scans;
};

class Driver {
 public:
  Driver(const DriverConfig& config, ScanHandler on_scan);

  void on_datagram(const LidarDatagram& datagram);

  const DecoderStats& stats() const { return stats_; }
  const Decoder& decoder() const { return decoder_; }
  const ScanAssembler& assembler() const { return assembler_; }

 private:
  Decoder decoder_;
  ScanAssembler assembler_;
  DecodedPacket packet_;  // reused for every packet
  DecoderStats stats_;
};

}  // namespace tumble::rs16
