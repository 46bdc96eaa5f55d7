// tumbled as systemd runs it: notification socket, watchdog, SIGTERM.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

TEST(TumbledProcess, AnLcmUrlThatCannotStartExitsOne) {
  const test::ProcessResult r = test::run_process({kTumbled, "--lcm-url", "nosuchprovider://x"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("lcm.url"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace tumble::daemon
