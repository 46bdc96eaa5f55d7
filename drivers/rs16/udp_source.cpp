#include "drivers/rs16/udp_source.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <time.h>

#include <boost/asio/ip/address_v4.hpp>
#include <boost/system/system_error.hpp>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace tumble::rs16 {
namespace {

// Per wake-up, so a flooded port cannot starve the other one.
constexpr int kMaxDatagramsPerWake = 64;

double realtime_now_s() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

// Linux reports twice the receive buffer asked for (socket(7): the rest is its
// bookkeeping); a sandbox's kernel (gVisor) may not. The factor is read off
// a buffer below any cap (net.core.rmem_max is at least 208 KiB by default).
int reported_buffer_factor(boost::asio::io_context& io) {
  constexpr int kSmall = 65536;
  boost::asio::ip::udp::socket probe(io, boost::asio::ip::udp::v4());
  probe.set_option(boost::asio::socket_base::receive_buffer_size(kSmall));
  boost::asio::socket_base::receive_buffer_size reported;
  probe.get_option(reported);
  return reported.value() >= 2 * kSmall ? 2 : 1;
}

}  // namespace

UdpSource::UdpSource(boost::asio::io_context& io, const UdpSourceConfig& config, Handler handler)
    : config_(config.ports), handler_(std::move(handler)), msop_(io, PacketKind::Msop), difop_(io, PacketKind::Difop) {
  if (config.ports.msop_port != 0 && config.ports.msop_port == config.ports.difop_port)
    throw std::invalid_argument("rs16.msop_port and rs16.difop_port are both " +
                                std::to_string(config.ports.msop_port) + ": they must differ");
  boost::system::error_code ec;
  const auto address = boost::asio::ip::make_address_v4(config.bind_address, ec);
  if (ec) throw std::runtime_error("rs16: bind_address '" + config.bind_address + "' is not an IPv4 address");
  open(msop_, address, config.ports.msop_port, config.receive_buffer_bytes);
  open(difop_, address, config.ports.difop_port, config.receive_buffer_bytes);
  boost::asio::socket_base::receive_buffer_size granted;
  msop_.socket.get_option(granted);
  granted_receive_buffer_bytes_ = granted.value() / reported_buffer_factor(io);
}

void UdpSource::open(Channel& channel, const boost::asio::ip::address_v4& address, std::uint16_t port,
                     int receive_buffer) {
  const boost::asio::ip::udp::endpoint endpoint(address, port);
  try {
    channel.socket.open(boost::asio::ip::udp::v4());
    channel.socket.set_option(boost::asio::socket_base::receive_buffer_size(receive_buffer));
    channel.socket.bind(endpoint);
  } catch (const boost::system::system_error& e) {
    throw BindError("rs16: cannot receive on UDP " + address.to_string() + ":" + std::to_string(port) + ": " +
                        e.code().message(),
                    e.code().value());
  }
  // Kernel receive times: no scheduling delay in what the clock mapper sees.
  const int on = 1;
  setsockopt(channel.socket.native_handle(), SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on));
  channel.socket.non_blocking(true);
}

void UdpSource::start() {
  running_ = true;
  arm(msop_);
  arm(difop_);
}

void UdpSource::stop() {
  running_ = false;
  boost::system::error_code ignored;
  msop_.socket.cancel(ignored);
  difop_.socket.cancel(ignored);
}

void UdpSource::arm(Channel& channel) {
  channel.socket.async_wait(boost::asio::ip::udp::socket::wait_read, [this, &channel](boost::system::error_code ec) {
    if (ec || !running_) return;
    drain(channel);
    if (running_) arm(channel);
  });
}

void UdpSource::drain(Channel& channel) {
  for (int i = 0; i < kMaxDatagramsPerWake && running_; ++i) {
    sockaddr_in from{};
    iovec iov{channel.buffer.data(), channel.buffer.size()};
    alignas(cmsghdr) std::array<char, CMSG_SPACE(sizeof(timespec))> control{};
    msghdr msg{};
    msg.msg_name = &from;
    msg.msg_namelen = sizeof(from);
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control.data();
    msg.msg_controllen = control.size();
    const ssize_t n = recvmsg(channel.socket.native_handle(), &msg, MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno != EAGAIN && errno != EWOULDBLOCK) ++stats_.receive_errors;
      return;
    }
    double arrival_s = 0.0;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
        timespec ts{};
        std::memcpy(&ts, CMSG_DATA(c), sizeof(ts));
        arrival_s = static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
      }
    }
    if (arrival_s == 0.0) arrival_s = realtime_now_s();
    if ((msg.msg_flags & MSG_TRUNC) != 0) {
      ++stats_.oversize;
      continue;
    }
    const std::uint32_t source_ip = ntohl(from.sin_addr.s_addr);
    if (config_.source_ip && source_ip != *config_.source_ip) {
      ++stats_.wrong_source;
      continue;
    }
    ++(channel.kind == PacketKind::Msop ? stats_.msop : stats_.difop);
    handler_(LidarDatagram{channel.kind, arrival_s, source_ip,
                           std::span<const std::uint8_t>(channel.buffer.data(), static_cast<std::size_t>(n))});
  }
}

}  // namespace tumble::rs16
