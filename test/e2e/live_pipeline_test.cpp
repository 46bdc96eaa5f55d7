// End to end with every real process: tumble-sim live plays the default
// extreme-motion scenario into loopback UDP and a pty (an MTi-30 that
// tumbled configures: the shipped imu.configure: true),
// tumbled runs LIVE on
// them (as systemd would start it), this test subscribes over LCM like any
// client (udpm, ttl=0) and lcm-logger records the same traffic for the jar
// test. Run inside a private network namespace (in_private_network.sh).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Geometry>

#include "test/daemon/notify_socket.hpp"
#include "test/daemon/process.hpp"
#include "test/e2e/child.hpp"
#include "tumble/odometry_t.hpp"
#include "tumble/registration_t.hpp"
#include "tumble/status_t.hpp"

namespace tumble::e2e {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kUrl = "udpm://239.255.76.67:7667?ttl=0";
constexpr double kImuRate_hz = 100.0;    // the default scenario's
constexpr double kScanRate_hz = 10.0;    // 600 rpm
constexpr double kMaxDrift_cm_per_m = 3.0;  // replay of this run: 0.37 (README, The default run)
constexpr double kMaxDrift_deg_per_m = 0.5;

struct Pose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};

// First and last poses of a TUM file, and the path length between them.
struct TumSpan {
  Pose first, last;
  double length_m = 0.0;
};

TumSpan read_tum_span(const fs::path& path) {
  std::ifstream in(path);
  TumSpan span;
  bool any = false;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t, x, y, z, qx, qy, qz, qw;
    fields >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
    const Pose pose{{x, y, z}, Eigen::Quaterniond(qw, qx, qy, qz)};
    if (!any) span.first = pose;
    if (any) span.length_m += (pose.p - span.last.p).norm();
    span.last = pose;
    any = true;
  }
  return span;
}

// What this test receives over LCM, and how old each message is on arrival
// (host clock minus its utime: the sample's or scan's first point's time).
struct Received {
  std::vector<tumble::odometry_t> odometry;
  std::vector<tumble::registration_t> poses;
  std::vector<double> odometry_age_ms, pose_age_ms;
  std::vector<double> odometry_latency_ms, pose_latency_ms;  // tumbled's own: input arrived -> handed to LCM
  tumble::status_t status{};
  void on_odometry(const lcm::ReceiveBuffer* buffer, const std::string&, const tumble::odometry_t* m) {
    odometry.push_back(*m);
    odometry_age_ms.push_back(static_cast<double>(buffer->recv_utime - m->utime) * 1e-3);
    odometry_latency_ms.push_back(m->latency_ms);
  }
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const tumble::status_t* m) { status = *m; }
  void on_pose(const lcm::ReceiveBuffer* buffer, const std::string&, const tumble::registration_t* m) {
    if (!m->registered) return;
    poses.push_back(*m);
    pose_age_ms.push_back(static_cast<double>(buffer->recv_utime - m->utime) * 1e-3);
    pose_latency_ms.push_back(m->latency_ms);
  }
};

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(p * static_cast<double>(values.size() - 1))];
}

template <class Message>
double rate_hz(const std::vector<Message>& messages) {
  if (messages.size() < 2) return 0.0;
  return static_cast<double>(messages.size() - 1) / ((messages.back().utime - messages.front().utime) * 1e-6);
}

Pose pose_of(const tumble::registration_t& m) {
  return {{m.position_m[0], m.position_m[1], m.position_m[2]},
          Eigen::Quaterniond(m.orientation[0], m.orientation[1], m.orientation[2], m.orientation[3])};
}

// Motion from a to b, seen from a.
Pose relative(const Pose& a, const Pose& b) { return {a.q.conjugate() * (b.p - a.p), a.q.conjugate() * b.q}; }

std::string line_after(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return {};
  const std::size_t start = at + key.size();
  return text.substr(start, text.find('\n', start) - start);
}

// How one live run went, beyond what run_live asserts itself.
struct LiveOutcome {
  bool sensor_data_dropped = false;  // then the machine is too loaded to judge the accuracy
  double translation_cm_per_m = 0.0;
  double rotation_deg_per_m = 0.0;
  std::string tumbled_log;
  bool within_bars() const {
    return translation_cm_per_m < kMaxDrift_cm_per_m && rotation_deg_per_m < kMaxDrift_deg_per_m;
  }
};

// One live run of the default scenario into dir (truth/ already there):
// asserts what must hold on every run, and measures the final pose error.
void run_live(const fs::path& dir, LiveOutcome& outcome) {
  const fs::path log_file = TUMBLE_E2E_LCM_LOG;
  fs::remove(log_file);
  lcm::LCM lcm(kUrl);
  ASSERT_TRUE(lcm.good()) << "LCM " << kUrl << " did not start: is multicast routed on lo?";
  Received received;
  lcm.subscribe("TUMBLE_ODOM", &Received::on_odometry, &received);
  lcm.subscribe("TUMBLE_POSE", &Received::on_pose, &received);
  lcm.subscribe("TUMBLE_STATUS", &Received::on_status, &received);

  Child logger({LCM_LOGGER, std::string("--lcm-url=") + kUrl, "-f", log_file.string()}, {}, dir / "lcm-logger");
  // The MTi waits in config state and the run starts once tumbled has
  // configured it, so tumbled sees the run's still start (its fuser levels there).
  Child sim({TUMBLE_SIM, "live", TUMBLE_E2E_SCENARIO, "--host", "127.0.0.1", "--mti-start", "config",
             "--start-when-measuring"},
            {}, dir / "sim");
  std::string pty;
  for (const auto until = Clock::now() + std::chrono::seconds(10); pty.empty() && Clock::now() < until;) {
    pty = line_after(sim.out(), "imu-pty ");
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_FALSE(pty.empty()) << sim.err();

  test::NotifySocket systemd;
  ASSERT_TRUE(systemd.bound());
  // The IMU path at the systemd unit's SCHED_FIFO priority (where the test
  // may not raise it, tumbled warns and goes on): at normal priority, on a
  // loaded machine, it stalled for 0.7 and 1.3 s and the runs ended 337 and
  // 7.9 cm/m off (README, The default run).
  Child tumbled({TUMBLED, "--lcm-url", kUrl, "--log-level", "info",
                 "--set", "imu.device=" + pty,
                 "--set", "lidar.bind_address=127.0.0.1", "--set", "lidar.clock=synced",
                 "--set", "lcm.publish_scan=true", "--set", "daemon.realtime_priority=20",
                 "--set", "imu.extrinsic_T_LI.translation_m=[0.02, 0, -0.08]",
                 "--trajectory-out", (dir / "live.tum").string()},
                {"NOTIFY_SOCKET=" + systemd.path()}, dir / "tumbled");

  bool ready = false;
  while (sim.running()) {
    lcm.handleTimeout(50);
    // Reads every pending notification: an unread socket queue would block tumbled's sd_notify.
    ready = systemd.wait_for("READY=1", 0).has_value() || ready;
    ASSERT_TRUE(tumbled.running()) << tumbled.err();
  }
  for (const auto until = Clock::now() + std::chrono::seconds(2); Clock::now() < until;) lcm.handleTimeout(50);
  tumbled.signal(SIGTERM);
  const std::optional<int> tumbled_exit = tumbled.wait_for(5.0);
  logger.signal(SIGINT);
  const std::optional<int> logger_exit = logger.wait_for(5.0);

  EXPECT_EQ(tumbled_exit, std::optional<int>(0)) << tumbled.err();
  EXPECT_TRUE(logger_exit.has_value()) << logger.err();
  EXPECT_TRUE(ready) << systemd.received();
  std::fprintf(stderr, "sim: %s", sim.err().c_str());

  // Rates over what was received, and nothing lost on the way.
  ASSERT_GT(received.odometry.size(), 100u) << tumbled.err();
  const double odom_hz = rate_hz(received.odometry), pose_hz = rate_hz(received.poses);
  const auto odometry_sent = received.odometry.back().seq - received.odometry.front().seq + 1;
  std::fprintf(stderr, "received TUMBLE_ODOM %zu at %.1f Hz (%lld sent), TUMBLE_POSE %zu registered at %.2f Hz\n",
               received.odometry.size(), odom_hz, static_cast<long long>(odometry_sent), received.poses.size(),
               pose_hz);
  // Figures only (not asserted: shared machines are noisy): the sample's age
  // includes the serial line and the IMU clock mapping; a scan's, its 0.1 s.
  std::fprintf(stderr, "age on arrival: TUMBLE_ODOM p50 %.2f ms p99 %.2f ms; TUMBLE_POSE p50 %.1f ms p99 %.1f ms\n",
               percentile(received.odometry_age_ms, 0.5), percentile(received.odometry_age_ms, 0.99),
               percentile(received.pose_age_ms, 0.5), percentile(received.pose_age_ms, 0.99));
  std::fprintf(stderr,
               "latency: IMU bytes read -> TUMBLE_ODOM published p50 %.3f ms p99 %.3f ms max %.3f ms; "
               "scan complete -> TUMBLE_POSE published p50 %.1f ms p99 %.1f ms\n",
               percentile(received.odometry_latency_ms, 0.5), percentile(received.odometry_latency_ms, 0.99),
               percentile(received.odometry_latency_ms, 1.0), percentile(received.pose_latency_ms, 0.5),
               percentile(received.pose_latency_ms, 0.99));
  // Every live sample and scan carries its latency (0 would mean the arrival
  // stamp was lost on the way through the threads).
  const auto positive = [](double ms) { return ms > 0.0; };
  EXPECT_TRUE(std::all_of(received.odometry_latency_ms.begin(), received.odometry_latency_ms.end(), positive));
  EXPECT_TRUE(std::all_of(received.pose_latency_ms.begin(), received.pose_latency_ms.end(), positive));
  // Registration is the one part that needs the CPU in real time (~50 ms per
  // 100 ms scan here). tumbled drops scans it cannot keep up with and says
  // so; then this machine is too loaded to judge live runs: their accuracy,
  // and the rates this test receives (its own socket overflowed on such a
  // run: 16 of 984 TUMBLE_ODOM lost, none dropped by tumbled).
  std::int64_t sensor_data_dropped = received.status.scans_dropped;
  std::string rings;
  for (int i = 0; i < received.status.num_rings; ++i) {
    const auto r = static_cast<std::size_t>(i);
    rings += " " + received.status.ring_name[r] + " " + std::to_string(received.status.ring_drops[r]);
    if (received.status.ring_name[r] != "odometry_out") sensor_data_dropped += received.status.ring_drops[r];
  }
  std::fprintf(stderr,
               "status: %s, scans dropped %lld, registered before the trajectory covered them %lld, "
               "weakly constrained %lld, untrusted %lld; IMU clock jitter %.2f ms; ring drops:%s\n",
               received.status.state_name.c_str(), static_cast<long long>(received.status.scans_dropped),
               static_cast<long long>(received.status.scans_short_trajectory),
               static_cast<long long>(received.status.scans_weakly_constrained),
               static_cast<long long>(received.status.scans_untrusted), received.status.imu_clock_jitter_s * 1e3,
               rings.c_str());
  outcome.tumbled_log = tumbled.err();
  if (sensor_data_dropped > 0) {
    std::fprintf(stderr, "tumbled dropped %lld items of sensor data\n", static_cast<long long>(sensor_data_dropped));
    outcome.sensor_data_dropped = true;
    return;
  }
  EXPECT_NEAR(odom_hz, kImuRate_hz, 0.05 * kImuRate_hz);
  EXPECT_GE(static_cast<double>(received.odometry.size()), 0.99 * static_cast<double>(odometry_sent));
  ASSERT_GT(received.poses.size(), 20u) << tumbled.err();
  EXPECT_NEAR(pose_hz, kScanRate_hz, 0.1 * kScanRate_hz);

  // The run starts and ends at rest: the motion first → last registered pose
  // against the truth's first → last pose, per metre travelled.
  const TumSpan gt = read_tum_span(dir / "truth" / "ground_truth.tum");
  ASSERT_GT(gt.length_m, 5.0);
  const Pose estimated = relative(pose_of(received.poses.front()), pose_of(received.poses.back()));
  const Pose expected = relative(gt.first, gt.last);
  const double translation_cm_per_m = 100.0 * (estimated.p - expected.p).norm() / gt.length_m;
  const double rotation_deg_per_m =
      Eigen::AngleAxisd(expected.q.conjugate() * estimated.q).angle() * 180.0 / M_PI / gt.length_m;
  std::fprintf(stderr, "live final pose error: %.2f cm/m, %.3f deg/m over %.2f m\n", translation_cm_per_m,
               rotation_deg_per_m, gt.length_m);
  outcome.translation_cm_per_m = translation_cm_per_m;
  outcome.rotation_deg_per_m = rotation_deg_per_m;
}

TEST(LiveEndToEnd, SimulatorToTumbledToLcmSubscribersAndLogger) {
  const fs::path dir = fs::path(TUMBLE_E2E_WORK_DIR);
  fs::remove_all(dir);
  fs::create_directories(dir);
  // The same run, written to files, for its ground truth.
  const test::ProcessResult truth =
      test::run_process({TUMBLE_SIM, "run", TUMBLE_E2E_SCENARIO, "--out", (dir / "truth").string()});
  ASSERT_EQ(truth.exit_code, 0) << truth.err;

  LiveOutcome outcome;
  ASSERT_NO_FATAL_FAILURE(run_live(dir, outcome));
  // One live run's error is one draw: the IMU's host times carry the
  // machine's scheduling jitter, and this run amplifies sub-ms differences.
  // Replays of one recording with imu_time_offset_s shifted by up to ±1 ms
  // end 0.34-0.53 or 1.5-1.8 cm/m off; by 5 ms, 4.9 or 20 (README, The
  // default run). A broken live chain misses on every run, so a miss gets
  // one more run and the second decides.
  std::string first_miss;
  if (!outcome.sensor_data_dropped && !outcome.within_bars()) {
    first_miss = "the first run missed the bars: " + std::to_string(outcome.translation_cm_per_m) + " cm/m, " +
                 std::to_string(outcome.rotation_deg_per_m) + " deg/m";
    std::fprintf(stderr, "%s; running it once more\n", first_miss.c_str());
    outcome = {};
    ASSERT_NO_FATAL_FAILURE(run_live(dir, outcome));
  }
  if (outcome.sensor_data_dropped)
    GTEST_SKIP() << "tumbled dropped sensor data: this machine is too loaded to run the registration in real time"
                 << (first_miss.empty() ? "" : " (" + first_miss + ")");
  EXPECT_LT(outcome.translation_cm_per_m, kMaxDrift_cm_per_m) << outcome.tumbled_log;
  EXPECT_LT(outcome.rotation_deg_per_m, kMaxDrift_deg_per_m) << outcome.tumbled_log;
}

}  // namespace
}  // namespace tumble::e2e
