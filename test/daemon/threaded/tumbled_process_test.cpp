// tumbled as systemd runs it: notification socket, watchdog, SIGTERM.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>

#include "test/daemon/notify_socket.hpp"
#include "test/daemon/process.hpp"

namespace tumble::daemon {
namespace {

namespace fs = std::filesystem;

const std::string kTumbled = std::string(TUMBLE_BINARY_DIR) + "/daemon/tumbled";

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// No sensor delivers here (no lidar traffic, no serial device): tumbled runs,
// pings the watchdog and reports its state, but is not READY. (READY after
// both sensors deliver: test/e2e.)
TEST(TumbledProcess, WithoutSensorsPingsTheWatchdogButIsNotReadyAndStopsOnSigterm) {
  test::NotifySocket socket;
  ASSERT_TRUE(socket.bound());
  const fs::path base = fs::temp_directory_path() / ("tumble_proc_" + std::to_string(::getpid()));
  const std::string out = base.string() + ".out", err = base.string() + ".err";
  const int port = 20000 + ::getpid() % 20000;  // nothing sends there; apart from other runs of this test
  const int pid = test::spawn_process({kTumbled, "--lcm-url", "memq://", "--log-level", "info", "--set",
                                       "imu.device=/nonexistent/tumble-test-tty", "--set",
                                       "lidar.bind_address=127.0.0.1", "--set", "lidar.msop_port=" + std::to_string(port),
                                       "--set", "lidar.difop_port=" + std::to_string(port + 1)},
                                      {"NOTIFY_SOCKET=" + socket.path(), "WATCHDOG_USEC=400000"}, out, err);
  const bool watchdog = socket.wait_for("WATCHDOG=1").has_value();
  const bool status = watchdog && socket.wait_for("STATUS=waiting_for_sensors").has_value();
  const bool more_pings = status && socket.wait_for("WATCHDOG=1").has_value();
  ::kill(pid, SIGTERM);
  const bool stopping = socket.wait_for("STOPPING=1").has_value();
  const int code = test::wait_process(pid);
  const std::string log = read_file(err);
  fs::remove(out);
  fs::remove(err);
  EXPECT_TRUE(watchdog) << log;
  EXPECT_TRUE(status) << log;
  EXPECT_TRUE(more_pings) << log;
  EXPECT_EQ(socket.received().find("READY=1"), std::string::npos) << socket.received();
  EXPECT_NE(log.find("mti: cannot open /nonexistent/tumble-test-tty"), std::string::npos) << log;
  EXPECT_TRUE(stopping) << log;
  EXPECT_EQ(code, 0) << log;
  EXPECT_NE(log.find("Terminated: stopping"), std::string::npos) << log;
  EXPECT_NE(log.find("stopped"), std::string::npos) << log;
}

// A UDP socket bound to 127.0.0.1:port, closed with the object; fd -1 when
// the port is taken.
class HeldPort {
 public:
  explicit HeldPort(int port) : fd_(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0)) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) release();
  }
  ~HeldPort() { release(); }
  HeldPort(const HeldPort&) = delete;
  HeldPort& operator=(const HeldPort&) = delete;
  bool held() const { return fd_ >= 0; }
  void release() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_;
};

bool eventually(const std::function<bool()>& condition, std::chrono::seconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

struct BindRetryRun {
  std::string log;
  int exit_code = -1;
  bool retried = false;   // the retry warning was logged while tumbled ran
  bool ran_on = false;    // and tumbled kept pinging the watchdog after it
};

// Starts tumbled on bind_address:port (and port+1), waits for its bind retry
// warning, calls while_retrying, then stops it with SIGTERM.
BindRetryRun run_with_bind_retry(const std::string& bind_address, int port, const std::function<void()>& while_retrying) {
  test::NotifySocket socket;
  const fs::path base = fs::temp_directory_path() / ("tumble_bind_" + std::to_string(::getpid()));
  const std::string out = base.string() + ".out", err = base.string() + ".err";
  const int pid = test::spawn_process({kTumbled, "--lcm-url", "memq://", "--log-level", "info", "--set",
                                       "imu.device=/nonexistent/tumble-test-tty", "--set",
                                       "lidar.bind_address=" + bind_address, "--set",
                                       "lidar.msop_port=" + std::to_string(port), "--set",
                                       "lidar.difop_port=" + std::to_string(port + 1)},
                                      {"NOTIFY_SOCKET=" + socket.path(), "WATCHDOG_USEC=400000"}, out, err);
  BindRetryRun run;
  run.retried = eventually([&] { return read_file(err).find("retrying in") != std::string::npos; },
                           std::chrono::seconds(10));
  if (run.retried) {
    while_retrying();
    run.ran_on = socket.wait_for("WATCHDOG=1", 5000).has_value() && socket.wait_for("WATCHDOG=1", 5000).has_value();
  }
  ::kill(pid, SIGTERM);
  run.exit_code = test::wait_process(pid);
  run.log = read_file(err);
  fs::remove(out);
  fs::remove(err);
  return run;
}

TEST(TumbledProcess, ABusyLidarPortIsRetriedUntilItIsFree) {
  const int port = 20000 + (::getpid() + 7) % 20000;
  HeldPort held(port);
  ASSERT_TRUE(held.held()) << "port " << port << " is in use here";
  bool bound_by_tumbled = false;
  const BindRetryRun run = run_with_bind_retry("127.0.0.1", port, [&] {
    held.release();
    // tumbled holds the port once it has retried: this test can no longer bind it.
    bound_by_tumbled = eventually([&] { return !HeldPort(port).held(); }, std::chrono::seconds(10));
  });
  EXPECT_TRUE(run.retried) << run.log;
  EXPECT_NE(run.log.find("Address already in use"), std::string::npos) << run.log;
  EXPECT_TRUE(bound_by_tumbled) << run.log;
  EXPECT_TRUE(run.ran_on) << run.log;
  EXPECT_NE(run.log.find("lidar: bound 127.0.0.1:" + std::to_string(port)), std::string::npos) << run.log;
  EXPECT_EQ(run.exit_code, 0) << run.log;
}

// 192.0.2.1 (TEST-NET-1) is assigned to no interface here.
TEST(TumbledProcess, AnAddressNotYetAssignedIsRetriedUntilShutdown) {
  const int port = 20000 + (::getpid() + 11) % 20000;
  const BindRetryRun run = run_with_bind_retry("192.0.2.1", port, [] {});
  EXPECT_TRUE(run.retried) << run.log;
  EXPECT_NE(run.log.find("Cannot assign requested address"), std::string::npos) << run.log;
  EXPECT_TRUE(run.ran_on) << run.log;
  EXPECT_EQ(run.exit_code, 0) << run.log;
  EXPECT_NE(run.log.find("Terminated: stopping"), std::string::npos) << run.log;
}

TEST(TumbledProcess, AnLcmUrlThatCannotStartExitsOne) {
  const test::ProcessResult r = test::run_process({kTumbled, "--lcm-url", "nosuchprovider://x"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("lcm.url"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace tumble::daemon
