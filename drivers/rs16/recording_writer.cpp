#include "drivers/rs16/recording_writer.hpp"

#include "drivers/pcap/udp_frame.hpp"

namespace tumble::rs16 {

RecordingWriter::RecordingWriter(const std::string& path, const RecordingAddresses& addresses)
    : writer_(path, pcap::kLinkEthernet), addresses_(addresses) {}

void RecordingWriter::write(std::int64_t arrival_t_ns, PacketKind kind, std::span<const std::uint8_t> payload) {
  write_from(addresses_.lidar_ip, arrival_t_ns, kind, payload);
}

void RecordingWriter::write_from(std::uint32_t source_ip, std::int64_t arrival_t_ns, PacketKind kind,
                                 std::span<const std::uint8_t> payload) {
  const std::uint16_t port = kind == PacketKind::Msop ? addresses_.msop_port : addresses_.difop_port;
  pcap::make_udp_ethernet_frame(source_ip, addresses_.host_ip, port, port, payload, frame_);
  writer_.write(arrival_t_ns, frame_);
}

}  // namespace tumble::rs16
