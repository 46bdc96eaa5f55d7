#include "tools/sim/live_sinks.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace tumble::sim {
namespace {

constexpr std::pair<speed_t, std::uint32_t> kSpeeds[] = {
    {B4800, 4800},     {B9600, 9600},     {B19200, 19200},   {B38400, 38400},   {B57600, 57600},
    {B115200, 115200}, {B230400, 230400}, {B460800, 460800}, {B921600, 921600}, {B2000000, 2000000},
};

[[noreturn]] void fail_errno(const std::string& what) { throw LiveError(what + ": " + std::strerror(errno)); }

}  // namespace

std::uint32_t parse_ipv4(const std::string& text) {
  in_addr addr{};
  if (inet_pton(AF_INET, text.c_str(), &addr) != 1) throw LiveError("'" + text + "' is not an IPv4 address");
  return ntohl(addr.s_addr);
}

bool is_loopback(std::uint32_t address) { return (address >> 24) == 127; }

UdpSender::UdpSender(std::uint32_t destination) : destination_(destination) {
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) fail_errno("UDP socket");
}

UdpSender::~UdpSender() {
  if (fd_ >= 0) ::close(fd_);
}

bool UdpSender::send(std::uint16_t port, std::span<const std::uint8_t> payload) {
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port);
  to.sin_addr.s_addr = htonl(destination_);
  const ssize_t n = ::sendto(fd_, payload.data(), payload.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
  // ECONNREFUSED only reports an earlier datagram nobody received.
  return n == static_cast<ssize_t>(payload.size()) || (n < 0 && errno == ECONNREFUSED);
}

ImuPty::ImuPty() {
  master_ = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master_ < 0) fail_errno("posix_openpt");
  if (::grantpt(master_) != 0) fail_errno("grantpt");
  if (::unlockpt(master_) != 0) fail_errno("unlockpt");
  char name[128];
  if (::ptsname_r(master_, name, sizeof name) != 0) fail_errno("ptsname_r");
  slave_path_ = name;
  slave_ = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (slave_ < 0) fail_errno(std::string("open ") + name);
  // Raw: the line discipline must pass binary frames through untouched.
  termios tio{};
  if (::tcgetattr(slave_, &tio) != 0) fail_errno("tcgetattr");
  ::cfmakeraw(&tio);
  ::cfsetispeed(&tio, B115200);
  ::cfsetospeed(&tio, B115200);
  if (::tcsetattr(slave_, TCSANOW, &tio) != 0) fail_errno("tcsetattr");
  const int flags = ::fcntl(master_, F_GETFL);
  if (flags < 0 || ::fcntl(master_, F_SETFL, flags | O_NONBLOCK) != 0) fail_errno("fcntl O_NONBLOCK");
}

ImuPty::~ImuPty() {
  if (slave_ >= 0) ::close(slave_);
  if (master_ >= 0) ::close(master_);
}

void ImuPty::write(std::span<const std::uint8_t> bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(master_, bytes.data(), bytes.size());
    if (n > 0) {
      bytes = bytes.subspan(static_cast<std::size_t>(n));
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    dropped_ += bytes.size();  // EAGAIN: nobody is reading fast enough
    return;
  }
}

void ImuPty::read_host(std::vector<std::uint8_t>& out) {
  std::uint8_t buffer[4096];
  for (;;) {
    const ssize_t n = ::read(master_, buffer, sizeof buffer);
    if (n > 0) {
      out.insert(out.end(), buffer, buffer + n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    return;  // EAGAIN: all read
  }
}

std::optional<std::uint32_t> ImuPty::line_baud() const {
  termios tio{};
  if (::tcgetattr(slave_, &tio) != 0) return std::nullopt;
  for (const auto& [speed, baud] : kSpeeds)
    if (::cfgetospeed(&tio) == speed) return baud;
  return std::nullopt;
}

bool ImuPty::set_line_baud(std::uint32_t baud) {
  for (const auto& [speed, b] : kSpeeds) {
    if (b != baud) continue;
    termios tio{};
    if (::tcgetattr(slave_, &tio) != 0) fail_errno("tcgetattr");
    ::cfsetispeed(&tio, speed);
    ::cfsetospeed(&tio, speed);
    if (::tcsetattr(slave_, TCSANOW, &tio) != 0) fail_errno("tcsetattr");
    return true;
  }
  return false;
}

}  // namespace tumble::sim
