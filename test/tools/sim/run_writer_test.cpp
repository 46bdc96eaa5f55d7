// A run folder: the two recordings, the ground truth and the manifest, and
// the promise that a seed gives the same bytes every time.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <sstream>

#include "drivers/pcap/pcap_file.hpp"
#include "drivers/pcap/udp_frame.hpp"
#include "test/tools/sim/sensor_test_support.hpp"
#include "tools/sim/run_writer.hpp"

namespace tumble::sim {
namespace {

using test::TempDir;

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A short turntable run in the box room: motion, so the skew and the IMU
// matter; 8 ms, as rays are slow under ASan.
Scenario short_run(const std::filesystem::path& dir, std::uint64_t seed) {
  test::BoxRoom room;
  const auto scene = room.write(dir);
  return parse_scenario(YAML::Load("scene: " + scene.string() +
                                   "\nmotion: {type: turntable, axis: [0, 0, 1], origin: {xyz_m: [0.5, -0.3, 1.1]},"
                                   " mount: {xyz_m: [0.1, 0, 0.2]},"
                                   " profile: [{hold_s: 0.001}, {ramp: {to_rad_s: 4, peak_rad_s2: 2000}}, {hold_s: 0.003}]}\n"
                                   "seed: " + std::to_string(seed) + "\nimu: {rate_hz: 400, baud: 921600}\n"),
                        "short.yaml", dir);
}

TEST(RunWriter, TheSameSeedGivesIdenticalBytesAndAnotherSeedDoesNot) {
  TempDir dir;
  const Scenario s1 = short_run(dir.path(), 11);
  write_run(SimRun(s1), dir.path() / "a");
  write_run(SimRun(s1), dir.path() / "b");
  write_run(SimRun(short_run(dir.path(), 12)), dir.path() / "c");
  for (const char* name : {kLidarPcapName, kImuPcapName, kGroundTruthName, kManifestName}) {
    SCOPED_TRACE(name);
    const std::string a = slurp(dir.path() / "a" / name);
    EXPECT_GT(a.size(), 100u);
    EXPECT_EQ(a, slurp(dir.path() / "b" / name));
  }
  EXPECT_NE(slurp(dir.path() / "a" / kLidarPcapName), slurp(dir.path() / "c" / kLidarPcapName));
  EXPECT_NE(slurp(dir.path() / "a" / kImuPcapName), slurp(dir.path() / "c" / kImuPcapName));
  // Only the motion decides the ground truth.
  EXPECT_EQ(slurp(dir.path() / "a" / kGroundTruthName), slurp(dir.path() / "c" / kGroundTruthName));
}

TEST(RunWriter, WritesTheRecordingsOnOneHostClockWithAManifest) {
  TempDir dir;
  const SimRun run(short_run(dir.path(), 3));
  const RunSummary summary = write_run(run, dir.path() / "out");
  const auto out = dir.path() / "out";
  for (const auto& e : std::filesystem::directory_iterator(out)) EXPECT_NE(e.path().extension(), ".tmp");

  // Lidar: Ethernet frames from 192.168.1.200, MSOP to 6699 and DIFOP to 7788, in time order.
  pcap::Reader lidar((out / kLidarPcapName).string());
  EXPECT_EQ(lidar.link_type(), pcap::kLinkEthernet);
  std::uint64_t msop = 0, difop = 0;
  std::int64_t first_ns = 0, last_ns = 0;
  while (const auto r = lidar.next()) {
    const auto udp = pcap::parse_udp_datagram(lidar.link_type(), r->bytes);
    ASSERT_TRUE(udp);
    EXPECT_EQ(udp->src_ip, kLidarIp);
    EXPECT_EQ(udp->payload.size(), 1248u);
    ++(udp->dst_port == 6699 ? msop : difop);
    EXPECT_TRUE(udp->dst_port == 6699 || udp->dst_port == 7788);
    EXPECT_GE(r->t_ns, last_ns);
    if (first_ns == 0) first_ns = r->t_ns;
    last_ns = r->t_ns;
  }
  EXPECT_EQ(msop, summary.msop_packets);
  EXPECT_EQ(difop, summary.difop_packets);
  EXPECT_NEAR(static_cast<double>(msop), run.duration_s() * 750.75, 2.0);
  const std::int64_t epoch = run.scenario().epoch_ns;
  EXPECT_GE(first_ns, epoch);
  EXPECT_LE(last_ns, epoch + static_cast<std::int64_t>(run.duration_s() * 1e9) + 5'000'000);

  // IMU: one record per serial read, on the same clock.
  pcap::Reader imu((out / kImuPcapName).string());
  EXPECT_EQ(imu.link_type(), pcap::kLinkUser0);
  std::uint64_t reads = 0, bytes = 0;
  while (const auto r = imu.next()) {
    ++reads;
    bytes += r->bytes.size();
    EXPECT_GE(r->t_ns, epoch);
    EXPECT_LE(r->t_ns, epoch + static_cast<std::int64_t>(run.duration_s() * 1e9) + 20'000'000);
  }
  EXPECT_EQ(reads, summary.imu_reads);
  EXPECT_EQ(bytes, summary.imu_frames * 54 + 5);  // 5 leading garbage bytes

  // Ground truth at 1 kHz from t = 0 to the end, host-clock seconds.
  std::ifstream gt(out / kGroundTruthName);
  std::string line;
  std::uint64_t poses = 0;
  double first_t = 0, last_t = 0;
  while (std::getline(gt, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t, x, y, z, qx, qy, qz, qw;
    ASSERT_TRUE(fields >> t >> x >> y >> z >> qx >> qy >> qz >> qw) << line;
    EXPECT_NEAR(qx * qx + qy * qy + qz * qz + qw * qw, 1.0, 1e-8);
    if (poses++ == 0) first_t = t;
    last_t = t;
  }
  EXPECT_EQ(poses, summary.ground_truth_poses);
  EXPECT_EQ(poses, static_cast<std::uint64_t>(std::floor(run.duration_s() * 1000 + 1e-6)) + 1);
  EXPECT_NEAR(first_t, static_cast<double>(epoch) * 1e-9, 1e-6);
  EXPECT_NEAR(last_t - first_t, std::floor(run.duration_s() * 1000 + 1e-6) / 1000, 1e-5);

  const YAML::Node m = YAML::LoadFile((out / kManifestName).string());
  EXPECT_EQ(m["seed"].as<std::uint64_t>(), 3u);
  EXPECT_EQ(m["files"]["lidar_pcap"].as<std::string>(), kLidarPcapName);
  EXPECT_EQ(m["files"]["imu_pcap"].as<std::string>(), kImuPcapName);
  EXPECT_EQ(m["files"]["ground_truth"].as<std::string>(), kGroundTruthName);
  EXPECT_EQ(m["epoch_ns"].as<std::int64_t>(), epoch);
  EXPECT_EQ(m["lidar"]["rpm"].as<int>(), 600);
  EXPECT_EQ(m["lidar"]["vertical_angles_deg"].size(), 16u);
  EXPECT_EQ(m["lidar"]["msop_packets"].as<std::uint64_t>(), msop);
  EXPECT_NEAR(m["imu"]["clock"]["drift_ppm"].as<double>(), run.imu_clock().drift_ppm, 1e-9);
  EXPECT_EQ(m["imu"]["clock"]["first_sample_time_fine"].as<std::uint32_t>(), run.imu_clock().first_sample_time_fine);
  EXPECT_EQ(m["extrinsics"]["T_LI"]["translation_m"].size(), 3u);
  EXPECT_EQ(m["motion_description"]["type"].as<std::string>(), "turntable");
}

}  // namespace
}  // namespace tumble::sim
