// run_daemon: the main thread's loop with fake parts.
#include "daemon/run.hpp"

#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>

#include "test/daemon/threaded/fake_parts.hpp"

namespace tumble::daemon {
namespace {

namespace fs = std::filesystem;

struct StatusInbox {
  std::vector<tumble::status_t> messages;
  void handle(const lcm::ReceiveBuffer*, const std::string&, const tumble::status_t* m) { messages.push_back(*m); }
};

class RunTest : public ::testing::Test {
 protected:
  void TearDown() override {
    fs::remove(trajectory_);
    fs::remove(trajectory_.string() + ".partial");
  }
  DaemonConfig config() const {
    DaemonConfig c;
    c.lcm.url = "memq://";
    return c;
  }
  fs::path trajectory_ = fs::temp_directory_path() / ("tumble_run_" + std::to_string(::getpid()) + ".tum");
  std::unique_ptr<fake::FakeRecording> recording_;  // outlives the pipeline inside run_daemon
};

TEST_F(RunTest, ReplayRunsToTheEndAndWritesTheTrajectory) {
  ShutdownSignals signals;
  lcm::LCM lcm("memq://");
  StatusInbox status;
  lcm.subscribe("TUMBLE_STATUS", &StatusInbox::handle, &status);
  RunOptions options;
  options.replay = ReplayFiles{"lidar.pcap", "imu.pcap"};
  options.rate.max = true;
  options.trajectory_out = trajectory_.string();
  constexpr int kScans = 6;
  const int code = run_daemon(config(), options, lcm, signals,
                              [&](boost::asio::io_context& io, const DaemonConfig&, const RunOptions&) {
                                recording_ = std::make_unique<fake::FakeRecording>(io, kScans);
                                return fake::make_parts(*recording_).parts;
                              });
  EXPECT_EQ(code, 0);
  std::ifstream in(trajectory_);
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  EXPECT_EQ(lines, kScans - 1);
  EXPECT_FALSE(fs::exists(trajectory_.string() + ".partial"));
  while (lcm.handleTimeout(0) > 0) {
  }
  ASSERT_FALSE(status.messages.empty());  // at least the final one
  EXPECT_EQ(status.messages.back().scans_registered, kScans - 1);
  EXPECT_EQ(status.messages.back().num_stages, 2);
}

TEST_F(RunTest, SigtermStopsALiveRunCleanly) {
  ShutdownSignals signals;
  lcm::LCM lcm("memq://");
  const pthread_t main_thread = pthread_self();
  RunOptions options;
  options.trajectory_out = trajectory_.string();
  const int code = run_daemon(config(), options, lcm, signals,
                              [&](boost::asio::io_context& io, const DaemonConfig&, const RunOptions&) {
                                recording_ = std::make_unique<fake::FakeRecording>(io, 50, /*ends=*/false);
                                recording_->before_event = [main_thread, sent = false](double t) mutable {
                                  if (sent || t < 1.0) return;
                                  sent = true;
                                  pthread_kill(main_thread, SIGTERM);
                                };
                                return fake::make_parts(*recording_).parts;
                              });
  EXPECT_EQ(code, 0);
  EXPECT_TRUE(fs::exists(trajectory_));  // committed, not left as .partial
}

TEST_F(RunTest, LiveInputThatEndsIsAFailure) {
  ShutdownSignals signals;
  lcm::LCM lcm("memq://");
  const int code = run_daemon(config(), RunOptions{}, lcm, signals,
                              [&](boost::asio::io_context& io, const DaemonConfig&, const RunOptions&) {
                                recording_ = std::make_unique<fake::FakeRecording>(io, 3);  // ends
                                return fake::make_parts(*recording_).parts;
                              });
  EXPECT_EQ(code, 1);
}

TEST_F(RunTest, ReplayWithoutReplaySourcesFails) {
  ShutdownSignals signals;
  lcm::LCM lcm("memq://");
  RunOptions options;
  options.replay = ReplayFiles{"lidar.pcap", "imu.pcap"};
  EXPECT_EQ(
      run_daemon(config(), options, lcm, signals,
                 [](boost::asio::io_context&, const DaemonConfig&, const RunOptions&) { return PipelineParts{}; }),
      1);
}

TEST_F(RunTest, AFailingThreadEndsTheRunWithExitCodeOne) {
  ShutdownSignals signals;
  lcm::LCM lcm("memq://");
  const int code = run_daemon(config(), RunOptions{}, lcm, signals,
                              [&](boost::asio::io_context& io, const DaemonConfig&, const RunOptions&) {
                                recording_ = std::make_unique<fake::FakeRecording>(io, 5, /*ends=*/false);
                                fake::FakeParts f = fake::make_parts(*recording_);
                                f.registration->on_register = [] { throw std::runtime_error("icp exploded"); };
                                return std::move(f.parts);
                              });
  EXPECT_EQ(code, 1);
}

}  // namespace
}  // namespace tumble::daemon
