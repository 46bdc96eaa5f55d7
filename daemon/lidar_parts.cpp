#include "daemon/lidar_parts.hpp"

#include "daemon/driver_params.hpp"

namespace tumble::daemon {

namespace {

std::uint16_t port_of(const rs16::SourceConfig& ports, rs16::PacketKind kind) {
  return kind == rs16::PacketKind::Msop ? ports.msop_port : ports.difop_port;
}

}  // namespace

LiveLidarSource::LiveLidarSource(boost::asio::io_context& io, const LidarConfig& config)
    : ports_(lidar_source_config(config)) {
  rs16::UdpSourceConfig udp;
  udp.bind_address = config.bind_address;
  udp.ports = ports_;
  udp.ports.source_ip.reset();
  udp_ = std::make_unique<rs16::UdpSource>(io, udp, [this](const rs16::LidarDatagram& d) {
    if (!on_datagram_) return;
    on_datagram_(LidarDatagram{d.arrival_s, d.source_ip, port_of(ports_, d.kind), port_of(ports_, d.kind), d.payload});
  });
}

void LiveLidarSource::start(std::function<void(const LidarDatagram&)> on_datagram, std::function<void()>) {
  on_datagram_ = std::move(on_datagram);  // live sockets never end
  udp_->start();
}

void LiveLidarSource::stop() {
  udp_->stop();
  on_datagram_ = nullptr;
}

Rs16LidarDecoder::Rs16LidarDecoder(const LidarConfig& config)
    : source_(lidar_source_config(config)), decoder_(lidar_decoder_config(config)), foreign_log_(1, 10.0) {}

bool Rs16LidarDecoder::decode(const LidarDatagram& datagram, PointBlock& block) {
  const std::optional<rs16::PacketKind> kind = rs16::kind_for_port(source_, datagram.dst_port);
  const bool wrong_sender = source_.source_ip && datagram.src_ip != *source_.source_ip;
  if (!kind || wrong_sender) {
    ++foreign_;
    foreign_log_.warn("foreign", datagram.arrival_s,
                      "lidar: ignoring datagrams from {} to port {} (lidar.source_ip {}, ports {}/{}); {} so far",
                      rs16::format_ipv4(datagram.src_ip), datagram.dst_port,
                      source_.source_ip ? rs16::format_ipv4(*source_.source_ip) : "any", source_.msop_port,
                      source_.difop_port, foreign_);
    return false;
  }
  if (*kind == rs16::PacketKind::Difop) {
    decoder_.decode_difop(datagram.payload, stats_);
    return false;
  }
  return decoder_.decode_msop(datagram.payload, datagram.arrival_s, block, stats_);
}

void Rs16LidarDecoder::report(PipelineCounters& counters) const {
  constexpr auto relaxed = std::memory_order_relaxed;
  counters.lidar_packets.store(static_cast<std::int64_t>(stats_.msop_packets), relaxed);
  counters.lidar_bad_packets.store(static_cast<std::int64_t>(stats_.bad_msop.total() + stats_.bad_difop.total()),
                                   relaxed);
  counters.lidar_foreign_packets.store(foreign_, relaxed);
  const rs16::LidarClockMapper& clock = decoder_.clock();
  if (clock.started()) {
    counters.lidar_clock.offset_s.store(clock.offset_s(), relaxed);
    counters.lidar_clock.drift_ppm.store(clock.drift() * 1e6, relaxed);
    counters.lidar_clock.jitter_s.store(clock.jitter_s(), relaxed);
  }
}

}  // namespace tumble::daemon
