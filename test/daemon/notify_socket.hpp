// A stand-in for systemd's notification socket: tumbled, started with
// NOTIFY_SOCKET pointing here, sends READY=1, WATCHDOG=1, STATUS=... to it.
#pragma once

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <filesystem>
#include <optional>
#include <string>

namespace tumble::test {

class NotifySocket {
 public:
  NotifySocket() : path_(std::filesystem::temp_directory_path() / ("tumble_sd_" + std::to_string(::getpid()))) {
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    path_.string().copy(address.sun_path, sizeof(address.sun_path) - 1);
    std::filesystem::remove(path_);
    bound_ = ::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
  }
  ~NotifySocket() {
    ::close(fd_);
    std::filesystem::remove(path_);
  }
  bool bound() const { return bound_; }
  // Every notification read so far, one per line.
  const std::string& received() const { return received_; }
  std::string path() const { return path_.string(); }

  // Reads notifications until one contains `wanted`; nullopt after silence_ms without any.
  std::optional<std::string> wait_for(const std::string& wanted, int silence_ms = 60'000) {
    for (;;) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, silence_ms) <= 0) return std::nullopt;
      char buffer[1024];
      const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
      if (n <= 0) return std::nullopt;
      const std::string message(buffer, static_cast<std::size_t>(n));
      received_ += message + "\n";
      if (message.find(wanted) != std::string::npos) return message;
    }
  }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  bool bound_ = false;
  std::string received_;
};

}  // namespace tumble::test
