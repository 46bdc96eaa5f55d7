// Live mode end to end on this machine: datagrams to 127.0.0.1 and IMU frames
// through the pty, read back as a daemon would. Short and bounded.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "drivers/mti/frame_reader.hpp"
#include "drivers/rs16/msop_decode.hpp"
#include "test/tools/sim/sensor_test_support.hpp"
#include "tools/sim/live.hpp"
#include "tools/sim/live_sinks.hpp"

namespace tumble::sim {
namespace {

using test::TempDir;

// An ostream target another thread can wait on, line by line.
class LineSink : public std::streambuf {
 public:
  // The first line starting with prefix, once written (or "" after timeout_s).
  std::string wait_for(const std::string& prefix, double timeout_s) {
    std::unique_lock lock(mutex_);
    std::string found;
    changed_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] {
      std::istringstream lines(text_);
      for (std::string line; std::getline(lines, line);) {
        if (line.rfind(prefix, 0) == 0 && lines.good()) {
          found = line;
          return true;
        }
      }
      return false;
    });
    return found;
  }

 protected:
  int_type overflow(int_type c) override {
    if (c != traits_type::eof()) {
      const std::lock_guard lock(mutex_);
      text_.push_back(static_cast<char>(c));
      changed_.notify_all();
    }
    return c;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::string text_;
};

// A UDP socket on 127.0.0.1 at a free port.
struct Receiver {
  int fd = -1;
  std::uint16_t port = 0;
  Receiver() {
    fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t n = sizeof a;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
    port = ntohs(a.sin_port);
  }
  ~Receiver() { ::close(fd); }
  // One datagram, or empty when none came within timeout_ms.
  std::vector<std::uint8_t> receive(int timeout_ms) const {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) != 1) return {};
    std::vector<std::uint8_t> buffer(2048);
    const ssize_t n = ::recv(fd, buffer.data(), buffer.size(), 0);
    buffer.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
    return buffer;
  }
};

Scenario box_room_scenario(const std::filesystem::path& dir) {
  test::BoxRoom room;
  const auto scene = room.write(dir);
  // A fast IMU so that frames come early in the stream (generation is slow under ASan).
  return parse_scenario(YAML::Load(test::box_room_scenario_yaml(scene, 2.0) +
                                   "lidar: {difop_phase_s: 0.0}\nimu: {rate_hz: 400, baud: 921600}\n"),
                        "live.yaml", dir);
}

TEST(Live, StreamsLidarOverUdpAndImuThroughAPty) {
  TempDir dir;
  const Scenario scenario = box_room_scenario(dir.path());
  Receiver msop, difop;
  LiveOptions options;
  options.msop_port = msop.port;
  options.difop_port = difop.port;
  options.duration_s = 5.0;  // a bound only: the test stops the player once it has read enough
  LineSink sink;
  std::ostream announce(&sink);
  std::atomic<bool> stop{false};
  LiveSummary summary;
  std::thread player([&] { summary = run_live(scenario, options, announce, stop); });

  const std::string pty_line = sink.wait_for("imu-pty ", 10.0);
  ASSERT_FALSE(pty_line.empty());
  const std::string pty_path = pty_line.substr(8);
  EXPECT_EQ(sink.wait_for("lidar-udp ", 1.0),
            "lidar-udp 127.0.0.1 " + std::to_string(msop.port) + " " + std::to_string(difop.port));
  const int tty = ::open(pty_path.c_str(), O_RDONLY | O_NOCTTY);
  ASSERT_GE(tty, 0) << pty_path;

  // The first DIFOP leaves at t = 0, then MSOP every 1.3 ms.
  const auto first_difop = difop.receive(3000);
  ASSERT_EQ(first_difop.size(), 1248u);
  EXPECT_EQ(first_difop[0], 0xA5);
  for (int i = 0; i < 5; ++i) {
    const auto packet = msop.receive(3000);
    ASSERT_EQ(packet.size(), 1248u);
    rs16::MsopHeader header;
    EXPECT_EQ(rs16::parse_msop_header(packet, header), rs16::PacketError::None);
  }

  // A few whole MTData2 frames out of the pty.
  mti::FrameReader frames;
  int mtdata2 = 0;
  std::vector<std::uint8_t> buffer(4096);
  for (int polls = 0; polls < 50 && mtdata2 < 3; ++polls) {
    pollfd p{tty, POLLIN, 0};
    if (::poll(&p, 1, 200) != 1) continue;
    const ssize_t n = ::read(tty, buffer.data(), buffer.size());
    if (n <= 0) break;
    frames.push(std::span(buffer).first(static_cast<std::size_t>(n)));
    while (const auto f = frames.next()) mtdata2 += f->mid == 0x36;
  }
  EXPECT_GE(mtdata2, 3);
  ::close(tty);

  // As on SIGINT: the player stops between two events and returns.
  stop = true;
  player.join();
  EXPECT_TRUE(summary.stopped);
  EXPECT_GE(summary.msop_packets, 5u);
  EXPECT_GE(summary.difop_packets, 1u);
  EXPECT_GE(summary.imu_reads, 3u);
  EXPECT_EQ(summary.udp_send_failures, 0u);
}

TEST(Live, StopsWhenAskedAndRefusesRemoteHosts) {
  TempDir dir;
  const Scenario scenario = box_room_scenario(dir.path());
  std::ostringstream announce;
  std::atomic<bool> stop{true};
  LiveOptions options;
  options.msop_port = 9;  // nothing is sent: stop is already raised
  options.difop_port = 9;
  const LiveSummary stopped = run_live(scenario, options, announce, stop);
  EXPECT_TRUE(stopped.stopped);
  EXPECT_EQ(stopped.msop_packets + stopped.imu_reads, 0u);
  EXPECT_EQ(announce.str().rfind("imu-pty /dev/pts/", 0), 0u) << announce.str();

  options.host = "192.168.1.102";
  EXPECT_THROW(run_live(scenario, options, announce, stop), LiveError);
  options.host = "localhost.example";
  EXPECT_THROW(run_live(scenario, options, announce, stop), LiveError);
  options.host = "127.0.0.1";
  options.rate = 0.0;
  EXPECT_THROW(run_live(scenario, options, announce, stop), LiveError);
}

}  // namespace
}  // namespace tumble::sim
