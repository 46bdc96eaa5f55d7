// tumbled (shipped default imu.configure: true) against tumble-sim live's
// MTi-30 on the pty, for the device as it should be and as it misbehaves:
// each case ends in tumbled's documented log line (daemon/README, "What a
// missing or wrong sensor looks like"), and tumbled stops cleanly on SIGTERM:
// never a hang. The lidar's datagrams go to ports nobody listens on: only the
// IMU is under test.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "test/daemon/notify_socket.hpp"
#include "test/e2e/child.hpp"

namespace tumble::e2e {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Standing still in the garage for longer than any case takes.
constexpr const char* kScenario = R"(scene: garage
motion: {type: static, duration_s: 12}
seed: 3
imu: {rate_hz: 100, baud: 115200}
)";

struct Outcome {
  bool found = false;
  std::string tumbled_log;
  std::string sim_log;
  double max_imu_hz = -1.0;  // the highest IMU rate tumbled's STATUS= lines reported
  std::optional<int> exit_code;
};

// STATUS= lines read "<state>; IMU <n> Hz, ..."; -1 when there was none.
double max_imu_rate_hz(const std::string& notifications) {
  double rate = -1.0;
  for (std::size_t at = notifications.find("; IMU "); at != std::string::npos;
       at = notifications.find("; IMU ", at + 1))
    rate = std::max(rate, std::stod(notifications.substr(at + 6)));
  return rate;
}

// Starts the simulator with sim_options and tumbled on its pty, waits up to
// timeout_s for `wanted` in tumbled's log, then stops both.
Outcome run_case(const std::string& name, const std::vector<std::string>& sim_options, const std::string& wanted,
                 double timeout_s, const std::vector<std::string>& tumbled_options = {}) {
  const fs::path dir = fs::path(TUMBLE_E2E_WORK_DIR) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scenario = dir / "still.yaml";
  std::ofstream(scenario) << kScenario;
  std::vector<std::string> sim_argv{TUMBLE_SIM, "live", scenario.string(), "--port-msop", "16699", "--port-difop",
                                    "17788"};
  sim_argv.insert(sim_argv.end(), sim_options.begin(), sim_options.end());
  Child sim(sim_argv, {}, dir / "sim");
  std::string pty;
  for (const auto until = Clock::now() + std::chrono::seconds(10); pty.empty() && Clock::now() < until;) {
    const std::string out = sim.out();
    const std::size_t at = out.find("imu-pty ");
    if (at != std::string::npos && out.find('\n', at) != std::string::npos)
      pty = out.substr(at + 8, out.find('\n', at) - at - 8);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  Outcome outcome;
  if (pty.empty()) {
    outcome.sim_log = sim.err();
    return outcome;
  }
  test::NotifySocket systemd;
  std::vector<std::string> tumbled_argv{TUMBLED,    "--config", TUMBLE_E2E_SHIPPED_CONFIG, "--lcm-url",
                                        "memq://",  "--log-level", "info", "--set", "imu.device=" + pty,
                                        "--set",    "lidar.bind_address=127.0.0.1"};
  tumbled_argv.insert(tumbled_argv.end(), tumbled_options.begin(), tumbled_options.end());
  Child tumbled(tumbled_argv, {"NOTIFY_SOCKET=" + systemd.path()}, dir / "tumbled");
  for (const auto until = Clock::now() + std::chrono::duration<double>(timeout_s);
       !outcome.found && Clock::now() < until && tumbled.running();) {
    systemd.wait_for("READY=1", 20);  // reads every pending notification
    outcome.found = tumbled.err().find(wanted) != std::string::npos;
  }
  // Two more STATUS= lines (one a second): whether IMU samples reach tumbled
  // after this (their rate is not judged: a loaded machine starves the player).
  for (const auto until = Clock::now() + std::chrono::milliseconds(2200); Clock::now() < until;)
    systemd.wait_for("READY=1", 20);
  outcome.max_imu_hz = max_imu_rate_hz(systemd.received());
  tumbled.signal(SIGTERM);
  outcome.exit_code = tumbled.wait_for(5.0);
  sim.signal(SIGINT);
  sim.wait_for(5.0);
  outcome.tumbled_log = tumbled.err();
  outcome.sim_log = sim.err();
  return outcome;
}

void expect_clean_stop(const Outcome& o) {
  EXPECT_EQ(o.exit_code, std::optional<int>(0)) << "tumbled did not stop on SIGTERM within 5 s\n" << o.tumbled_log;
}

TEST(MtiHandshake, ConfiguresADeviceWaitingInConfigState) {
  const Outcome o = run_case("config_state", {"--mti-start", "config"}, "measuring at 100 Hz", 4.0);
  EXPECT_TRUE(o.found) << o.tumbled_log << o.sim_log;
  EXPECT_NE(o.tumbled_log.find("MTi-30-2A8G4 (id 03700123, firmware 1.8.2 build 37 rev 70964)"), std::string::npos)
      << o.tumbled_log;
  EXPECT_GT(o.max_imu_hz, 0.0) << o.tumbled_log;
  expect_clean_stop(o);
}

TEST(MtiHandshake, ConfiguresADeviceThatIsAlreadyStreaming) {
  const Outcome o = run_case("streaming", {"--mti-start", "measuring"}, "measuring at 100 Hz", 4.0);
  EXPECT_TRUE(o.found) << o.tumbled_log << o.sim_log;
  EXPECT_GT(o.max_imu_hz, 0.0) << o.tumbled_log;
  expect_clean_stop(o);
}

TEST(MtiHandshake, AcknowledgesTheWakeUpOfADevicePoweringUp) {
  const Outcome o = run_case("wake_up", {"--mti-start", "wake-up"}, "measuring at 100 Hz", 4.0);
  EXPECT_TRUE(o.found) << o.tumbled_log << o.sim_log;
  EXPECT_GT(o.max_imu_hz, 0.0) << o.tumbled_log;
  expect_clean_stop(o);
}

TEST(MtiHandshake, SilentDeviceIsReportedAndRetried) {
  const Outcome o = run_case("silent", {"--mti-silent"}, "reconnecting in", 5.0);
  EXPECT_TRUE(o.found) << o.tumbled_log << o.sim_log;
  EXPECT_NE(o.tumbled_log.find("configuring " ), std::string::npos) << o.tumbled_log;
  EXPECT_NE(o.tumbled_log.find("no GoToConfigAck within 2.0 s at 115200 baud"), std::string::npos) << o.tumbled_log;
  EXPECT_EQ(o.max_imu_hz, 0.0);
  expect_clean_stop(o);
}

TEST(MtiHandshake, PortAtAnotherBaudThanTheDeviceIsReportedAsNoAnswer) {
  // The device stays at 115200; tumbled's port at 460800 reads nothing it can use.
  const Outcome o = run_case("wrong_baud", {"--mti-start", "config"}, "reconnecting in", 5.0,
                             {"--set", "imu.baud=460800"});
  EXPECT_TRUE(o.found) << o.tumbled_log << o.sim_log;
  EXPECT_NE(o.tumbled_log.find("no GoToConfigAck within 2.0 s at 460800 baud"), std::string::npos) << o.tumbled_log;
  EXPECT_NE(o.sim_log.find("MTi: 0 requests"), std::string::npos) << o.sim_log;
  EXPECT_EQ(o.max_imu_hz, 0.0);
  expect_clean_stop(o);
}

TEST(MtiHandshake, LateAnswersWithinTheTimeoutStillConfigure) {
  // 0.6 s: past the 0.5 s resend, inside the 2 s timeout.
  const Outcome o = run_case("late", {"--mti-start", "config", "--mti-reply-delay", "0.6"}, "measuring at 100 Hz",
                             5.5);
  EXPECT_TRUE(o.found) << o.tumbled_log << o.sim_log;
  EXPECT_GT(o.max_imu_hz, 0.0) << o.tumbled_log;
  expect_clean_stop(o);
}

TEST(MtiHandshake, AnswersAfterTheTimeoutFailTheStep) {
  const Outcome o = run_case("too_late", {"--mti-start", "config", "--mti-reply-delay", "2.5"}, "reconnecting in", 5.0);
  EXPECT_TRUE(o.found) << o.tumbled_log << o.sim_log;
  EXPECT_NE(o.tumbled_log.find("no GoToConfigAck within 2.0 s"), std::string::npos) << o.tumbled_log;
  EXPECT_EQ(o.max_imu_hz, 0.0);
  expect_clean_stop(o);
}

TEST(MtiHandshake, UnknownProductCodeIsWarnedAbout) {
  const Outcome o =
      run_case("product_code", {"--mti-product-code", "MTi-7-XYZ"}, "product code 'MTi-7-XYZ' names no gyro range", 4.0);
  EXPECT_TRUE(o.found) << o.tumbled_log << o.sim_log;
  EXPECT_NE(o.tumbled_log.find("measuring at 100 Hz"), std::string::npos) << o.tumbled_log;
  EXPECT_GT(o.max_imu_hz, 0.0) << o.tumbled_log;
  expect_clean_stop(o);
}

TEST(MtiHandshake, DeviceErrorIsReportedWithItsCode) {
  const Outcome o = run_case("device_error", {"--mti-refuse", "C0:33"}, "reconnecting in", 4.0);
  EXPECT_TRUE(o.found) << o.tumbled_log << o.sim_log;
  EXPECT_NE(o.tumbled_log.find("the MTi answered SetOutputConfiguration with error 33 (parameter invalid)"),
            std::string::npos)
      << o.tumbled_log;
  EXPECT_EQ(o.max_imu_hz, 0.0);
  expect_clean_stop(o);
}

}  // namespace
}  // namespace tumble::e2e
