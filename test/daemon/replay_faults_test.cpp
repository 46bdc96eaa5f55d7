// tumbled replaying a short simulated cage run with one sensor gap mid-tumble,
// or its lidar starting mid-tumble (tumble-sim faults): the health states on
// data time, the same on every replay, and a final error of at most 5 cm/m.
// And a recording whose lidar datagrams arrived late: byte-identical
// trajectories whatever the thread count and the machine's load, and at real
// time the same trajectory as long as nothing is dropped.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <thread>
#include <string>
#include <vector>

#include "daemon/lidar_parts.hpp"
#include "daemon/pcap_recorder.hpp"
#include "drivers/pcap/pcap_file.hpp"
#include "drivers/rs16/pcap_source.hpp"
#include "test/core/synthetic_room.hpp"
#include "test/daemon/process.hpp"
#include "test/temp_dir.hpp"
#include "tools/eval/run_score.hpp"

namespace tumble::daemon {
namespace {

namespace fs = std::filesystem;

const std::string kBin = TUMBLE_BINARY_DIR;

// The "state a -> b: reason (data time t s)" lines, without the wall-clock prefix.
std::vector<std::string> state_lines(const std::string& log) {
  std::vector<std::string> lines;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);) {
    const auto at = line.find("state ");
    if (at != std::string::npos && line.find("data time") != std::string::npos) lines.push_back(line.substr(at));
  }
  return lines;
}

bool contains(const std::vector<std::string>& lines, const std::string& text) {
  for (const std::string& line : lines)
    if (line.find(text) != std::string::npos) return true;
  return false;
}

class ReplayFaults : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("replay-faults");
    if (test::kCoarseTests) return;
    const test::ProcessResult sim = test::run_process(
        {kBin + "/tools/sim/tumble-sim", "run", "--out", (dir_->path() / "run").string(), "--duration", "7"});
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
  }
  static void TearDownTestSuite() { delete dir_; }
  void SetUp() override {
    // Debug (sanitizer) builds simulate and replay tens of times slower: over ten minutes for this run.
    if (test::kCoarseTests) GTEST_SKIP() << "simulating and replaying a run takes many minutes in unoptimised builds";
  }

  struct Replay {
    std::vector<std::string> states;
    double cm_per_m = 0.0;
  };

  static fs::path inject(const std::string& name, const std::vector<std::string>& fault) {
    const fs::path out = dir_->path() / name;
    std::vector<std::string> argv = {kBin + "/tools/sim/tumble-sim", "faults", (dir_->path() / "run").string(),
                                     out.string()};
    argv.insert(argv.end(), fault.begin(), fault.end());
    const test::ProcessResult faults = test::run_process(argv);
    EXPECT_EQ(faults.exit_code, 0) << faults.err;
    return out;
  }

  // Returns tumbled's output (log lines); the trajectory goes to `trajectory`.
  static std::string run_tumbled(const fs::path& recording, const fs::path& trajectory,
                                 const std::vector<std::string>& options = {}, const std::string& rate = "max") {
    std::vector<std::string> argv = {kBin + "/daemon/tumbled",    "--replay",
                                     (recording / "lidar.pcap").string(), (recording / "imu.pcap").string(),
                                     "--rate",                    rate,
                                     "--lcm-url",                 "memq://",
                                     "--trajectory-out",          trajectory.string()};
    argv.insert(argv.end(), options.begin(), options.end());
    const test::ProcessResult run = test::run_process(argv);
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return run.out + run.err;
  }

  static Replay replay_with(const std::string& name, const std::vector<std::string>& fault) {
    const fs::path out = inject(name, fault);
    const fs::path trajectory = out / "trajectory.tum";
    const std::string log = run_tumbled(out, trajectory);
    Replay replay;
    replay.states = state_lines(log);
    replay.cm_per_m = eval::score_run(out / "ground_truth.tum", trajectory, std::nullopt, {}).drift.translation_cm_per_m;
    return replay;
  }

  static test::TempDir* dir_;
};

test::TempDir* ReplayFaults::dir_ = nullptr;

// The cage starts rolling at 1.5 s; the gaps are mid-tumble.
TEST_F(ReplayFaults, AnImuGapIsReportedWithinASecondAndBridged) {
  const Replay replay = replay_with("imu-gap", {"--imu-gap", "4,1"});
  // Degraded for this reason, whether the state was tracking or already degraded.
  EXPECT_TRUE(contains(replay.states, "degraded: no IMU data (data time 4.")) << ::testing::PrintToString(replay.states);
  EXPECT_LE(replay.cm_per_m, 5.0);
}

TEST_F(ReplayFaults, ALidarGapIsReportedWithinASecondAndBridgedTheSameOnEveryReplay) {
  const Replay first = replay_with("lidar-gap", {"--lidar-gap", "4,0.5"});
  EXPECT_TRUE(contains(first.states, "degraded: no lidar data (data time 4.")) << ::testing::PrintToString(first.states);
  EXPECT_LE(first.cm_per_m, 5.0);
  const Replay second = replay_with("lidar-gap-again", {"--lidar-gap", "4,0.5"});
  EXPECT_EQ(second.states, first.states);
}

// The lidar's first data 0.4 s into the 10 rad/s pull, past the gyro's range:
// no first scan can be de-skewed whole, so no map starts (before, the map
// started there and the run said tracking while it ended 29 cm/m off).
TEST_F(ReplayFaults, ALidarThatStartsMidPullStartsNoMapWhileTheGyroIsClipped) {
  const fs::path out = inject("lidar-starts-mid-pull", {"--lidar-gap", "0,1.9"});
  const std::vector<std::string> states = state_lines(run_tumbled(out, out / "trajectory.tum"));
  EXPECT_TRUE(contains(states, "state initialising: no local map yet: the gyro is clipped"))
      << ::testing::PrintToString(states);
  EXPECT_FALSE(contains(states, "-> tracking")) << ::testing::PrintToString(states);
  EXPECT_EQ(fs::file_size(out / "trajectory.tum"), 0u) << "a pose was registered";
}

// A lidar restart: silent for 2 s from 3 s, then a new header clock. Past 1 s
// of silence the IMU alone carried the pose too far to trust a match with the
// old map: lost (not tracking on a drifted pose), then a new map and tracking.
TEST_F(ReplayFaults, ALidarRestartIsLostWithinASecondThenANewMapTracks) {
  const Replay replay = replay_with("lidar-restart", {"--lidar-gap", "3,2", "--lidar-clock-jump", "5,-50"});
  const std::string states = ::testing::PrintToString(replay.states);
  EXPECT_TRUE(contains(replay.states, "lost: no lidar data for too long: the pose is the IMU's alone (data time 4.0") ||
              contains(replay.states, "lost: no lidar data for too long: the pose is the IMU's alone (data time 4.1"))
      << states;
  EXPECT_TRUE(contains(replay.states, "lost -> initialising: re-initialised: new local map (data time 5.")) << states;
  EXPECT_TRUE(contains(replay.states, "initialising -> tracking: first scan registered (data time 5.")) << states;
  EXPECT_FALSE(contains(replay.states, "lost -> tracking")) << "tracking again on the old map:\n" << states;
}

std::string contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Spinning threads, one per core, for as long as it lives.
class CpuLoad {
 public:
  CpuLoad() {
    for (unsigned i = 0; i < std::max(1u, std::thread::hardware_concurrency()); ++i)
      threads_.emplace_back([this] {
        while (!stop_.load(std::memory_order_relaxed)) {
        }
      });
  }
  ~CpuLoad() {
    stop_.store(true, std::memory_order_relaxed);
    for (std::thread& t : threads_) t.join();
  }
  CpuLoad(const CpuLoad&) = delete;
  CpuLoad& operator=(const CpuLoad&) = delete;

 private:
  std::atomic<bool> stop_{false};
  std::vector<std::thread> threads_;
};

// Which trajectory a scan is placed with may not depend on how the threads
// were scheduled: the arrival times shift how lidar and IMU interleave, the
// thread counts and the load shift which thread runs ahead.
TEST_F(ReplayFaults, ALateArrivingRecordingGivesTheSameTrajectoryWhateverTheThreadsAndLoad) {
  const fs::path late = inject("lidar-late", {"--lidar-delay", "0.005", "--seed", "3"});
  run_tumbled(late, late / "quiet.tum");
  const std::string quiet = contents(late / "quiet.tum");
  ASSERT_FALSE(quiet.empty());
  CpuLoad load;
  for (const char* threads : {"1", "4"}) {
    const fs::path loaded = late / (std::string("loaded-") + threads + ".tum");
    run_tumbled(late, loaded, {"--set", std::string("daemon.registration_threads=") + threads});
    EXPECT_EQ(contents(loaded), quiet) << "registration threads " << threads;
  }
}

// At real time the replay runs as live: the IMU's output is not held back
// for the registration, so a scan's correction reaches the fuser some
// samples after the scan ends, how many depending on the threads. The
// trajectory may not depend on it (before, 3 of 4 real-time replays of this
// recording differed from the lossless one). A machine too busy to keep up
// drops data, as a live run must, and then the trajectory differs.
TEST_F(ReplayFaults, ARealTimeReplayThatKeepsUpGivesTheLosslessTrajectory) {
  const fs::path late = inject("lidar-late-real-time", {"--lidar-delay", "0.005", "--seed", "3"});
  run_tumbled(late, late / "lossless.tum");
  const std::string lossless = contents(late / "lossless.tum");
  ASSERT_FALSE(lossless.empty());
  int compared = 0;
  for (const char* threads : {"1", "2"}) {
    const fs::path real_time = late / (std::string("real-time-") + threads + ".tum");
    const std::string log =
        run_tumbled(late, real_time, {"--set", std::string("daemon.registration_threads=") + threads}, "1");
    const auto final_status = log.find("final status:");
    const std::string status_line =
        final_status == std::string::npos ? "" : log.substr(final_status, log.find('\n', final_status) - final_status);
    if (status_line.find(", 0 dropped") == std::string::npos) {
      std::cerr << "registration threads " << threads << ": the replay dropped data (machine too busy), not compared\n";
      continue;
    }
    ++compared;
    EXPECT_EQ(contents(real_time), lossless) << "registration threads " << threads;
  }
  if (compared == 0) GTEST_SKIP() << "both real-time replays dropped data: the machine was too busy to compare";
}

// What tumbled's recorder keeps of a run with foreign datagrams on the wire
// (those the decoder takes as the lidar's, with their sender, and every
// serial read) replays to the trajectory the run itself gives.
TEST_F(ReplayFaults, TheRecordersRecordingReplaysToTheSameTrajectory) {
  const fs::path wire = inject("foreign-on-the-wire", {"--foreign-lidar", "0.05", "--seed", "5"});
  const rs16::SourceConfig ports;
  RecordConfig record;
  record.dir = (wire / "recorded").string();
  record.min_free_mib = 0;
  PipelineCounters counters;
  std::vector<std::string> segments;
  {
    PcapRecorder recorder(record, ports, 2.0);
    Rs16LidarDecoder decoder(LidarConfig{});
    rs16::PcapSource lidar((wire / "lidar.pcap").string(), ports);
    PointBlock block;
    int fed = 0;
    const auto pace = [&fed] {  // the recorder's ring holds 4096 items: let its writer keep up
      if (++fed % 1000 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(200));
    };
    int foreign = 0;
    while (const auto d = lidar.next()) {
      const std::uint16_t port = d->kind == rs16::PacketKind::Msop ? ports.msop_port : ports.difop_port;
      const LidarDatagram datagram{d->arrival_s, d->source_ip, port, port, d->payload};
      decoder.decode(datagram, block);
      if (!decoder.last_from_the_lidar()) {
        ++foreign;
        continue;
      }
      recorder.record_lidar(datagram);
      pace();
    }
    EXPECT_GT(foreign, 0) << "the fault put no foreign datagram on the wire";
    pcap::Reader imu((wire / "imu.pcap").string());
    while (const auto r = imu.next()) {
      recorder.record_imu(ImuBytes{static_cast<double>(r->t_ns) * 1e-9, r->bytes});
      pace();
    }
    recorder.flush();
    recorder.report(counters);
    segments = recorder.segments();
  }
  EXPECT_EQ(counters.record_dropped.load(), 0);
  EXPECT_EQ(counters.record_errors.load(), 0);
  ASSERT_EQ(segments.size(), 1u);
  run_tumbled(wire, wire / "wire.tum");
  run_tumbled(segments[0], wire / "recorded.tum");
  ASSERT_FALSE(contents(wire / "wire.tum").empty());
  EXPECT_EQ(contents(wire / "recorded.tum"), contents(wire / "wire.tum"));
}

}  // namespace
}  // namespace tumble::daemon
