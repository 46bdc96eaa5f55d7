// Receives the lidar's MSOP and DIFOP datagrams live on two UDP ports with
// Boost.Asio. Each datagram is stamped with its kernel receive time (host
// CLOCK_REALTIME, SO_TIMESTAMPNS) and handed to the handler from a fixed
// buffer: nothing is allocated per datagram.
#pragma once

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

#include "drivers/rs16/lidar_datagram.hpp"

namespace tumble::rs16 {

struct UdpSourceConfig {
  std::string bind_address = "0.0.0.0";
  SourceConfig ports;  // port 0 in tests: let the kernel pick (see msop_port())
  int receive_buffer_bytes = 4 << 20;  // room for ~3 s of MSOP at full rate if the io thread stalls
};

struct UdpSourceStats {
  std::uint64_t msop = 0;
  std::uint64_t difop = 0;
  std::uint64_t wrong_source = 0;
  std::uint64_t oversize = 0;  // larger than any lidar packet, skipped
  std::uint64_t receive_errors = 0;
};

// A port could not be bound: the message names address:port and the reason,
// error_number is the errno (EADDRINUSE, EADDRNOTAVAIL, EACCES, ...).
class BindError : public std::runtime_error {
 public:
  BindError(const std::string& message, int error_number) : std::runtime_error(message), error_number_(error_number) {}
  int error_number() const { return error_number_; }

 private:
  int error_number_;
};

class UdpSource {
 public:
  // The payload is valid only during the call: copy it (e.g. into a ring) to keep it.
  using Handler = std::function<void(const LidarDatagram&)>;

  // Binds both ports; throws BindError naming address:port and the reason,
  // std::runtime_error for an address that is not IPv4, std::invalid_argument
  // when the two ports are the same.
  UdpSource(boost::asio::io_context& io, const UdpSourceConfig& config, Handler handler);
  UdpSource(const UdpSource&) = delete;
  UdpSource& operator=(const UdpSource&) = delete;

  // Starts receiving on the io_context's thread(s); stop() ends that.
  void start();
  void stop();

  std::uint16_t msop_port() const { return msop_.socket.local_endpoint().port(); }
  // What the kernel granted the MSOP socket: it caps the request at
  // net.core.rmem_max without an error, so this may be below the config's.
  int granted_receive_buffer_bytes() const { return granted_receive_buffer_bytes_; }
  std::uint16_t difop_port() const { return difop_.socket.local_endpoint().port(); }
  const UdpSourceStats& stats() const { return stats_; }

 private:
  static constexpr std::size_t kBufferBytes = 2048;  // an MSOP/DIFOP payload is 1248
  struct Channel {
    Channel(boost::asio::io_context& io, PacketKind k) : socket(io), kind(k) {}
    boost::asio::ip::udp::socket socket;
    PacketKind kind;
    std::array<std::uint8_t, kBufferBytes> buffer{};
  };

  void open(Channel& channel, const boost::asio::ip::address_v4& address, std::uint16_t port, int receive_buffer);
  void arm(Channel& channel);
  void drain(Channel& channel);

  SourceConfig config_;
  Handler handler_;
  Channel msop_;
  Channel difop_;
  UdpSourceStats stats_;
  int granted_receive_buffer_bytes_ = 0;
  bool running_ = false;
};

}  // namespace tumble::rs16
