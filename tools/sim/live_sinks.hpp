// Where live mode puts the bytes: UDP datagrams to the lidar ports, and a
// pseudo-terminal that stands in for the IMU's serial port.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace tumble::sim {

struct LiveError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// IPv4 dotted quad to a host-order address; throws LiveError naming the text.
std::uint32_t parse_ipv4(const std::string& text);
bool is_loopback(std::uint32_t address);

class UdpSender {
 public:
  explicit UdpSender(std::uint32_t destination);
  ~UdpSender();
  UdpSender(const UdpSender&) = delete;
  UdpSender& operator=(const UdpSender&) = delete;

  // False when the kernel refused the datagram (nobody listening is not an error).
  bool send(std::uint16_t port, std::span<const std::uint8_t> payload);

 private:
  int fd_ = -1;
  std::uint32_t destination_;
};

// The master side of a pty in raw mode. We keep the slave open too, so its
// raw settings hold and writes succeed before a reader attaches; a full
// buffer drops bytes (counted), like a UART overrun.
class ImuPty {
 public:
  ImuPty();
  ~ImuPty();
  ImuPty(const ImuPty&) = delete;
  ImuPty& operator=(const ImuPty&) = delete;

  const std::string& slave_path() const { return slave_path_; }
  void write(std::span<const std::uint8_t> bytes);
  std::uint64_t dropped_bytes() const { return dropped_; }
  // Appends what the host wrote to its end (never blocks).
  void read_host(std::vector<std::uint8_t>& out);
  int master_fd() const { return master_; }
  // The speed the host set on the port; nullopt for one termios has no number for.
  std::optional<std::uint32_t> line_baud() const;
  // Sets the port's speed, as a device's line has it before a host changes
  // it; false for a speed termios has no constant for.
  bool set_line_baud(std::uint32_t baud);

 private:
  int master_ = -1;
  int slave_ = -1;
  std::string slave_path_;
  std::uint64_t dropped_ = 0;
};

}  // namespace tumble::sim
