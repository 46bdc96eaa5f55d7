#include "daemon/systemd_notify.hpp"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

namespace tumble::daemon {
namespace {

// A datagram socket standing in for systemd's notification socket.
class FakeNotifySocket {
 public:
  FakeNotifySocket() {
    path_ = (std::filesystem::temp_directory_path() / ("tumble_notify_" + std::to_string(::getpid()))).string();
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    path_.copy(address.sun_path, sizeof(address.sun_path) - 1);
    std::filesystem::remove(path_);
    bound_ = ::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
    ::setenv("NOTIFY_SOCKET", path_.c_str(), 1);
  }
  ~FakeNotifySocket() {
    ::unsetenv("NOTIFY_SOCKET");
    ::close(fd_);
    std::filesystem::remove(path_);
  }
  bool bound() const { return bound_; }
  // The next datagram already sent (sd_notify is synchronous), if any.
  std::optional<std::string> next() {
    char buffer[512];
    const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
    if (n < 0) return std::nullopt;
    return std::string(buffer, static_cast<std::size_t>(n));
  }

 private:
  std::string path_;
  int fd_ = -1;
  bool bound_ = false;
};

TEST(SystemdNotifier, IsANoOpWithoutSystemd) {
  ::unsetenv("NOTIFY_SOCKET");
  const SystemdNotifier notifier;
  EXPECT_FALSE(notifier.active());
  EXPECT_TRUE(notifier.ready());
  EXPECT_TRUE(notifier.watchdog());
  EXPECT_TRUE(notifier.stopping());
}

TEST(SystemdNotifier, SendsTheProtocolMessages) {
  FakeNotifySocket socket;
  ASSERT_TRUE(socket.bound());
  const SystemdNotifier notifier;
  EXPECT_TRUE(notifier.active());
  EXPECT_TRUE(notifier.ready());
  EXPECT_EQ(socket.next(), "READY=1");
  EXPECT_TRUE(notifier.status("tracking; IMU 100 Hz\nsecond line"));
  EXPECT_EQ(socket.next(), "STATUS=tracking; IMU 100 Hz second line");
  EXPECT_TRUE(notifier.watchdog());
  EXPECT_EQ(socket.next(), "WATCHDOG=1");
  EXPECT_TRUE(notifier.stopping());
  EXPECT_EQ(socket.next(), "STOPPING=1");
  EXPECT_EQ(socket.next(), std::nullopt);
}

TEST(SystemdNotifier, ReadsTheWatchdogTimeoutForThisProcess) {
  ::setenv("WATCHDOG_USEC", "5000000", 1);
  ::setenv("WATCHDOG_PID", std::to_string(::getpid()).c_str(), 1);
  const SystemdNotifier mine;
  ASSERT_TRUE(mine.watchdog_timeout());
  EXPECT_EQ(*mine.watchdog_timeout(), std::chrono::seconds(5));
  ::setenv("WATCHDOG_PID", std::to_string(::getpid() + 1).c_str(), 1);
  EXPECT_FALSE(SystemdNotifier().watchdog_timeout());  // meant for another process
  ::unsetenv("WATCHDOG_USEC");
  ::unsetenv("WATCHDOG_PID");
  EXPECT_FALSE(SystemdNotifier().watchdog_timeout());
}

}  // namespace
}  // namespace tumble::daemon
