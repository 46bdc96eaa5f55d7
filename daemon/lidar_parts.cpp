#include "daemon/lidar_parts.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <string>

#include "daemon/driver_params.hpp"

namespace tumble::daemon {

namespace {

// 750.75 MSOP packets of 1248 bytes a second (docs/sensors.md, single return), with
// the kernel's per-packet overhead about doubling what a buffer holds.
constexpr double kMsopBytesPerSecond = 750.75 * 1248 * 2;

std::uint16_t port_of(const rs16::SourceConfig& ports, rs16::PacketKind kind) {
  return kind == rs16::PacketKind::Msop ? ports.msop_port : ports.difop_port;
}

}  // namespace

LiveLidarSource::LiveLidarSource(boost::asio::io_context& io, const LidarConfig& config)
    : config_(config), ports_(lidar_source_config(config)), io_(io), retry_timer_(io) {
  try_bind();
}

bool LiveLidarSource::try_bind() {
  rs16::UdpSourceConfig udp;
  udp.bind_address = config_.bind_address;
  udp.ports = ports_;
  udp.ports.source_ip.reset();
  udp.receive_buffer_bytes = config_.receive_buffer_bytes;
  try {
    udp_ = std::make_unique<rs16::UdpSource>(io_, udp, [this](const rs16::LidarDatagram& d) {
      if (!on_datagram_) return;
      on_datagram_(
          LidarDatagram{d.arrival_s, d.source_ip, port_of(ports_, d.kind), port_of(ports_, d.kind), d.payload});
    });
  } catch (const rs16::BindError& e) {
    if (e.error_number() != EADDRINUSE && e.error_number() != EADDRNOTAVAIL) throw;
    if (failed_binds_++ == 0) first_failure_ = std::chrono::steady_clock::now();
    spdlog::warn("lidar: {} (lidar.bind_address, lidar.msop_port/difop_port); retrying in {:.2f} s, attempt {}, "
                 "until it binds or tumbled stops",
                 e.what(), std::chrono::duration<double>(retry_delay_).count(), failed_binds_);
    return false;
  }
  if (failed_binds_ > 0)
    spdlog::info("lidar: bound {}:{}/{} after {} failed attempts over {:.1f} s", config_.bind_address,
                 ports_.msop_port, ports_.difop_port, failed_binds_,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - first_failure_).count());
  const int granted = udp_->granted_receive_buffer_bytes();
  if (granted < config_.receive_buffer_bytes)
    spdlog::warn("lidar: the kernel granted {} KiB of socket receive buffer, below lidar.receive_buffer_bytes ({} KiB): "
                 "a stall of the io thread longer than {:.2f} s loses lidar packets. Raise net.core.rmem_max "
                 "(the package's /usr/lib/sysctl.d/60-tumble.conf, then `sysctl --system`)",
                 granted / 1024, config_.receive_buffer_bytes / 1024, granted / kMsopBytesPerSecond);
  return true;
}

void LiveLidarSource::retry_later() {
  retry_timer_.expires_after(retry_delay_);
  retry_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || stopped_) return;
    retry_delay_ = std::min(retry_delay_ * 2, kLongestRetryDelay);
    if (try_bind())
      udp_->start();
    else
      retry_later();
  });
}

void LiveLidarSource::start(std::function<void(const LidarDatagram&)> on_datagram, std::function<void()>) {
  on_datagram_ = std::move(on_datagram);  // live sockets never end
  if (udp_)
    udp_->start();
  else
    retry_later();
}

void LiveLidarSource::stop() {
  stopped_ = true;
  retry_timer_.cancel();
  if (udp_) udp_->stop();
  on_datagram_ = nullptr;
}

Rs16LidarDecoder::Rs16LidarDecoder(const LidarConfig& config)
    : source_(lidar_source_config(config)),
      decoder_(lidar_decoder_config(config)),
      lidar_(source_.source_ip),
      fault_log_(1, 10.0) {}

bool Rs16LidarDecoder::decode(const LidarDatagram& datagram, PointBlock& block) {
  foreign_msop_rate_.advance(datagram.arrival_s);
  const std::optional<rs16::PacketKind> kind = rs16::kind_for_port(source_, datagram.dst_port);
  last_from_the_lidar_ = kind && lidar_.may_be_lidar(datagram.src_ip);
  if (!last_from_the_lidar_) {
    if (kind == rs16::PacketKind::Msop) foreign_msop_rate_.count();
    ignore(datagram);
    return false;
  }
  if (*kind == rs16::PacketKind::Difop) {
    decoder_.decode_difop(datagram.payload, stats_);
    return false;
  }
  const std::uint64_t bad_before = stats_.bad_msop.total();
  const double offset_before_s = decoder_.clock().offset_s();
  const bool decoded = decoder_.decode_msop(datagram.payload, datagram.arrival_s, block, stats_);
  if (stats_.bad_msop.total() == bad_before && lidar_.lock_on(datagram.src_ip))
    spdlog::info("lidar: the lidar is {}, the first sender of MSOP datagrams (lidar.source_ip not set); datagrams "
                 "from any other address are ignored until tumbled restarts",
                 rs16::format_ipv4(datagram.src_ip));
  if (decoder_.clock().resets() > clock_resets_) {
    clock_resets_ = decoder_.clock().resets();
    fault_log_.warn("clock jump", datagram.arrival_s,
                    "lidar: header clock jumped by {:+.3f} s against arrival times: clock mapping restarted; {} so far",
                    offset_before_s - decoder_.clock().offset_s(), clock_resets_);
  }
  return decoded;
}

void Rs16LidarDecoder::ignore(const LidarDatagram& datagram) {
  ++foreign_;
  const std::string lidar = !lidar_.lidar()        ? std::string("none yet")
                            : source_.source_ip ? rs16::format_ipv4(*lidar_.lidar()) + " (lidar.source_ip)"
                                                : rs16::format_ipv4(*lidar_.lidar()) + " (the first sender)";
  fault_log_.warn("foreign", datagram.arrival_s,
                  "lidar: ignoring datagrams from {} to port {} (the lidar is {}, ports {}/{}); {} so far",
                  rs16::format_ipv4(datagram.src_ip), datagram.dst_port, lidar, source_.msop_port,
                  source_.difop_port, foreign_);
}

void Rs16LidarDecoder::report(PipelineCounters& counters) const {
  constexpr auto relaxed = std::memory_order_relaxed;
  counters.lidar_packets.store(static_cast<std::int64_t>(stats_.msop_packets), relaxed);
  counters.lidar_bad_packets.store(static_cast<std::int64_t>(stats_.bad_msop.total() + stats_.bad_difop.total()),
                                   relaxed);
  counters.lidar_foreign_packets.store(foreign_, relaxed);
  counters.lidar_difop_ignored.store(static_cast<std::int64_t>(stats_.difop_ignored), relaxed);
  counters.lidar_foreign_rate_hz.store(foreign_msop_rate_.rate_hz(), relaxed);
  const rs16::LidarClockMapper& clock = decoder_.clock();
  if (clock.started()) {
    counters.lidar_clock.offset_s.store(clock.offset_s(), relaxed);
    counters.lidar_clock.drift_ppm.store(clock.drift() * 1e6, relaxed);
    counters.lidar_clock.jitter_s.store(clock.jitter_s(), relaxed);
  }
}

}  // namespace tumble::daemon
