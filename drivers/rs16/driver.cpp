#include "drivers/rs16/driver.hpp"

namespace tumble::rs16 {

Driver::Driver(const DriverConfig& config, ScanHandler on_scan)
    : decoder_(config.decoder), assembler_(config.scans, std::move(on_scan)) {}

void Driver::on_datagram(const LidarDatagram& d) {
  if (d.kind == PacketKind::Difop) {
    decoder_.decode_difop(d.payload, stats_);
  } else if (decoder_.decode_msop(d.payload, d.arrival_s, packet_, stats_)) {
    assembler_.add(packet_, stats_);
  }
}

}  // namespace tumble::rs16
