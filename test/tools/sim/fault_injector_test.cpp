// tumble-sim faults: each fault does what it says on a small run written with
// the project's recording writers, the same seed gives the same bytes, and
// the ground truth and manifest come through untouched.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <set>

#include "drivers/mti/imu_recording_writer.hpp"
#include "drivers/pcap/pcap_file.hpp"
#include "drivers/pcap/udp_frame.hpp"
#include "drivers/rs16/difop_encode.hpp"
#include "drivers/rs16/laser_geometry.hpp"
#include "drivers/rs16/msop_encode.hpp"
#include "drivers/rs16/packet_layout.hpp"
#include "drivers/rs16/recording_writer.hpp"
#include "drivers/rs16/utc_time.hpp"
#include "test/temp_dir.hpp"
#include "tools/sim/fault_injector.hpp"
#include "tools/sim/run_writer.hpp"
#include "tools/sim/wire_faults.hpp"
#include "drivers/rs16/difop_decode.hpp"

namespace tumble::sim {
namespace {

namespace fs = std::filesystem;
using tumble::test::TempDir;

constexpr std::int64_t kStartNs = 1'700'000'000'000'000'000;
constexpr std::int64_t kMsopPeriodNs = 1'200'000;
constexpr std::int64_t kImuPeriodNs = 2'500'000;
constexpr int kMsopCount = 1000;  // 1.2 s
constexpr int kImuReads = 480;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// MSOP packet i: its first block azimuth says which packet it is (0.01 deg
// units), its header time is its arrival time minus a millisecond.
std::array<std::uint8_t, rs16::kPacketSize> msop(int i) {
  rs16::MsopPacketData p;
  p.utc_time_ns = kStartNs + i * kMsopPeriodNs - 1'000'000;
  p.blocks[0].azimuth_deg = i * 0.01;
  return rs16::encode_msop(p);
}

int packet_id(std::span<const std::uint8_t> payload) {
  return rs16::read_u16_be(payload, rs16::kFirstBlockOffset + rs16::kBlockAzimuthOffset);
}

std::int64_t header_time_ns(std::span<const std::uint8_t> payload, std::size_t offset = rs16::kMsopTimeOffset) {
  return *rs16::decode_utc_time_ns(payload.subspan(offset).first<rs16::kUtcTimeSize>());
}

std::vector<std::uint8_t> imu_read(int i) {
  return {0xFA, 0xFF, 0x36, static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(i >> 8), 0x55};
}

// A run folder as `tumble-sim run` lays it out, small enough for ASan.
fs::path write_small_run(const fs::path& dir) {
  fs::create_directories(dir);
  {
    rs16::RecordingWriter lidar((dir / kLidarPcapName).string());
    for (int i = 0; i < kMsopCount; ++i) {
      const std::int64_t t = kStartNs + i * kMsopPeriodNs;
      lidar.write(t, rs16::PacketKind::Msop, msop(i));
      rs16::DifopData difop;
      difop.utc_time_ns = t;
      difop.vertical_angles_deg = rs16::kDesignVerticalAnglesDeg;
      if (i % 84 == 0) lidar.write(t + 1000, rs16::PacketKind::Difop, rs16::encode_difop(difop));
    }
  }
  {
    mti::ImuRecordingWriter imu((dir / kImuPcapName).string());
    for (int i = 0; i < kImuReads; ++i) imu.write(kStartNs + 100'000 + i * kImuPeriodNs, imu_read(i));
  }
  std::ofstream(dir / kGroundTruthName) << "1700000000.0 0 0 0 0 0 0 1\n1700000001.0 1 0 0 0 0 0 1\n";
  std::ofstream(dir / kManifestName) << "scenario: small\nseed: 1\n";
  return dir;
}

struct LidarOut {
  std::int64_t t_ns;
  std::uint32_t src_ip;
  std::uint16_t dst_port;
  std::vector<std::uint8_t> payload;
};

std::vector<LidarOut> read_lidar(const fs::path& path) {
  pcap::Reader reader(path.string());
  std::vector<LidarOut> out;
  while (const auto r = reader.next()) {
    const auto udp = pcap::parse_udp_datagram(reader.link_type(), r->bytes);
    EXPECT_TRUE(udp.has_value());
    out.push_back({r->t_ns, udp->src_ip, udp->dst_port, {udp->payload.begin(), udp->payload.end()}});
  }
  return out;
}

std::vector<LidarOut> msops(const std::vector<LidarOut>& all) {
  std::vector<LidarOut> out;
  for (const auto& d : all)
    if (d.dst_port == 6699) out.push_back(d);
  return out;
}

std::vector<std::pair<std::int64_t, std::vector<std::uint8_t>>> read_imu(const fs::path& path) {
  pcap::Reader reader(path.string());
  std::vector<std::pair<std::int64_t, std::vector<std::uint8_t>>> out;
  while (const auto r = reader.next()) out.emplace_back(r->t_ns, std::vector<std::uint8_t>(r->bytes.begin(), r->bytes.end()));
  return out;
}

class FaultInjector : public ::testing::Test {
 protected:
  FaultCounts inject(const FaultPlan& plan, const std::string& name = "out") {
    return inject_faults(run_, dir_.path() / name, plan);
  }
  fs::path out(const std::string& name = "out") const { return dir_.path() / name; }

  TempDir dir_;
  fs::path run_ = write_small_run(dir_.path() / "run");
};

TEST_F(FaultInjector, AnEmptyPlanCopiesTheRunAndCarriesGroundTruthAndManifest) {
  const FaultCounts c = inject({});
  EXPECT_EQ(c.msop_packets, static_cast<std::uint64_t>(kMsopCount));
  EXPECT_EQ(c.imu_reads, static_cast<std::uint64_t>(kImuReads));
  EXPECT_DOUBLE_EQ(c.run_start_s, static_cast<double>(kStartNs) * 1e-9);
  for (const char* name : {kLidarPcapName, kImuPcapName, kGroundTruthName, kManifestName}) {
    SCOPED_TRACE(name);
    EXPECT_EQ(slurp(out() / name), slurp(run_ / name));
  }
  const YAML::Node record = YAML::LoadFile((out() / kFaultsName).string());
  EXPECT_EQ(record["injected"]["msop_packets"].as<int>(), kMsopCount);
  EXPECT_EQ(record["seed"].as<int>(), 1);
}

TEST_F(FaultInjector, TheSameSeedGivesTheSameBytesAndAnotherSeedDoesNot) {
  FaultPlan plan;
  plan.drop_lidar = plan.dup_lidar = plan.swap_lidar = plan.foreign_lidar = plan.imu_garbage = 0.05;
  inject(plan, "a");
  inject(plan, "b");
  plan.seed = 2;
  inject(plan, "c");
  for (const char* name : {kLidarPcapName, kImuPcapName}) {
    SCOPED_TRACE(name);
    EXPECT_EQ(slurp(out("a") / name), slurp(out("b") / name));
    EXPECT_NE(slurp(out("a") / name), slurp(out("c") / name));
  }
}

TEST_F(FaultInjector, DropLosesAboutThatShareOfMsopPacketsAndNothingElse) {
  FaultPlan plan;
  plan.drop_lidar = 0.05;
  const FaultCounts c = inject(plan);
  EXPECT_GT(c.lidar_dropped, 25u);
  EXPECT_LT(c.lidar_dropped, 80u);
  const auto all = read_lidar(out() / kLidarPcapName);
  const auto m = msops(all);
  EXPECT_EQ(m.size(), kMsopCount - c.lidar_dropped);
  EXPECT_EQ(all.size() - m.size(), c.difop_packets);
  for (std::size_t i = 1; i < m.size(); ++i) EXPECT_LT(packet_id(m[i - 1].payload), packet_id(m[i].payload));
  EXPECT_EQ(slurp(out() / kImuPcapName), slurp(run_ / kImuPcapName));
}

TEST_F(FaultInjector, DuplicatesFollowTheirOriginalByteForByte) {
  FaultPlan plan;
  plan.dup_lidar = 0.02;
  const FaultCounts c = inject(plan);
  EXPECT_GT(c.lidar_duplicated, 5u);
  const auto m = msops(read_lidar(out() / kLidarPcapName));
  ASSERT_EQ(m.size(), kMsopCount + c.lidar_duplicated);
  std::uint64_t repeats = 0;
  for (std::size_t i = 1; i < m.size(); ++i) {
    EXPECT_LT(m[i - 1].t_ns, m[i].t_ns);
    if (m[i].payload == m[i - 1].payload) ++repeats;
    else EXPECT_EQ(packet_id(m[i].payload), packet_id(m[i - 1].payload) + 1);
  }
  EXPECT_EQ(repeats, c.lidar_duplicated);
}

TEST_F(FaultInjector, SwapsExchangeNeighboursAndKeepArrivalTimesInOrder) {
  FaultPlan plan;
  plan.swap_lidar = 0.02;
  const FaultCounts c = inject(plan);
  EXPECT_GT(c.lidar_swapped_pairs, 5u);
  const auto m = msops(read_lidar(out() / kLidarPcapName));
  ASSERT_EQ(m.size(), static_cast<std::size_t>(kMsopCount));
  std::uint64_t swapped = 0;
  std::set<int> ids;
  for (std::size_t i = 0; i < m.size(); ++i) {
    EXPECT_EQ(m[i].t_ns, kStartNs + static_cast<std::int64_t>(i) * kMsopPeriodNs);
    const int id = packet_id(m[i].payload);
    ids.insert(id);
    if (id != static_cast<int>(i)) {
      // Only ever with a neighbour: i holds i + 1 and i + 1 holds i.
      ASSERT_EQ(id, static_cast<int>(i) + 1);
      ASSERT_LT(i + 1, m.size());
      EXPECT_EQ(packet_id(m[i + 1].payload), static_cast<int>(i));
      ++swapped;
      ++i;
      ids.insert(static_cast<int>(i) - 1);
    }
  }
  EXPECT_EQ(swapped, c.lidar_swapped_pairs);
  EXPECT_EQ(ids.size(), static_cast<std::size_t>(kMsopCount));
}

TEST_F(FaultInjector, ForeignDatagramsComeFromAnotherSenderWithPacketsOfTheRun) {
  FaultPlan plan;
  plan.foreign_lidar = 0.05;
  const FaultCounts c = inject(plan);
  EXPECT_GT(c.lidar_foreign, 25u);
  std::uint64_t foreign = 0;
  for (const auto& d : msops(read_lidar(out() / kLidarPcapName))) {
    if (d.src_ip == kLidarIp) continue;
    EXPECT_EQ(d.src_ip, kForeignLidarIp);
    EXPECT_EQ(d.payload.size(), rs16::kPacketSize);
    const int id = packet_id(d.payload);
    const auto original = msop(id);
    EXPECT_EQ(std::vector<std::uint8_t>(original.begin(), original.end()), d.payload);
    ++foreign;
  }
  EXPECT_EQ(foreign, c.lidar_foreign);
}

TEST_F(FaultInjector, ALidarGapRemovesEveryLidarDatagramInItsWindowOnly) {
  FaultPlan plan;
  plan.lidar_gap = FaultWindow{0.3, 0.5};
  const FaultCounts c = inject(plan);
  const auto all = read_lidar(out() / kLidarPcapName);
  EXPECT_EQ(all.size() + c.lidar_gap_dropped, kMsopCount + c.difop_packets);
  EXPECT_GE(c.lidar_gap_dropped, 416u);  // 0.5 s of 1.2 ms packets
  for (const auto& d : all) EXPECT_TRUE(d.t_ns < kStartNs + 300'000'000 || d.t_ns >= kStartNs + 800'000'000);
  EXPECT_EQ(slurp(out() / kImuPcapName), slurp(run_ / kImuPcapName));
  const YAML::Node record = YAML::LoadFile((out() / kFaultsName).string());
  EXPECT_DOUBLE_EQ(record["plan"]["lidar_gap"]["host_start_s"].as<double>(), c.run_start_s + 0.3);
}

TEST_F(FaultInjector, AnImuGapRemovesTheSerialReadsInItsWindowOnly) {
  FaultPlan plan;
  plan.imu_gap = FaultWindow{0.2, 0.25};
  const FaultCounts c = inject(plan);
  const auto reads = read_imu(out() / kImuPcapName);
  EXPECT_EQ(c.imu_gap_dropped, 100u);
  EXPECT_EQ(reads.size(), kImuReads - c.imu_gap_dropped);
  for (const auto& [t, bytes] : reads) EXPECT_TRUE(t < kStartNs + 200'000'000 || t >= kStartNs + 450'000'000);
  EXPECT_EQ(slurp(out() / kLidarPcapName), slurp(run_ / kLidarPcapName));
}

TEST_F(FaultInjector, GarbagePrecedesSomeSerialReadsAndKeepsTheirBytes) {
  FaultPlan plan;
  plan.imu_garbage = 0.05;
  const FaultCounts c = inject(plan);
  EXPECT_GT(c.imu_garbled_reads, 8u);
  const auto reads = read_imu(out() / kImuPcapName);
  ASSERT_EQ(reads.size(), static_cast<std::size_t>(kImuReads));
  std::uint64_t garbled = 0, extra = 0;
  for (int i = 0; i < kImuReads; ++i) {
    const auto original = imu_read(i);
    const auto& bytes = reads[i].second;
    ASSERT_GE(bytes.size(), original.size());
    const std::size_t n = bytes.size() - original.size();
    EXPECT_LE(n, 40u);
    EXPECT_TRUE(std::equal(original.begin(), original.end(), bytes.begin() + static_cast<std::ptrdiff_t>(n)));
    if (n > 0) ++garbled;
    extra += n;
  }
  EXPECT_EQ(garbled, c.imu_garbled_reads);
  EXPECT_EQ(extra, c.imu_garbage_bytes);
}

TEST_F(FaultInjector, AClockJumpMovesTheHeaderTimesFromItsMomentOn) {
  FaultPlan plan;
  plan.lidar_clock_jump = ClockJump{0.6, 5.0};
  const FaultCounts c = inject(plan);
  const auto all = read_lidar(out() / kLidarPcapName);
  ASSERT_EQ(all.size(), kMsopCount + c.difop_packets);
  std::uint64_t jumped = 0, msop_index = 0;
  for (const auto& d : all) {
    const bool after = d.t_ns >= kStartNs + 600'000'000;
    const std::int64_t shift = after ? 5'000'000'000 : 0;
    if (d.dst_port == 6699) {
      const std::int64_t original = kStartNs + static_cast<std::int64_t>(msop_index++) * kMsopPeriodNs - 1'000'000;
      EXPECT_EQ(header_time_ns(d.payload), original + shift);
    } else {
      EXPECT_EQ(header_time_ns(d.payload, rs16::kDifopTimeOffset), d.t_ns - 1000 + shift);
    }
    jumped += after;
  }
  EXPECT_EQ(c.lidar_clock_jumped, jumped);
  EXPECT_GT(jumped, 300u);
}

TEST_F(FaultInjector, AStalledMotorHoldsEveryBlockAzimuthInItsWindowOnly) {
  FaultPlan plan;
  plan.motor_stall = FaultWindow{0.3, 0.5};
  const FaultCounts c = inject(plan);
  const auto all = msops(read_lidar(out() / kLidarPcapName));
  ASSERT_EQ(all.size(), static_cast<std::size_t>(kMsopCount));
  std::uint64_t stalled = 0;
  std::optional<std::uint16_t> held;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const bool in_stall = all[i].t_ns >= kStartNs + 300'000'000 && all[i].t_ns < kStartNs + 800'000'000;
    const auto original = msop(static_cast<int>(i));
    if (!in_stall) {
      EXPECT_EQ(std::vector<std::uint8_t>(original.begin(), original.end()), all[i].payload) << i;
      continue;
    }
    // Where the head was: the last block of the packet the stall began with.
    if (!held) held = rs16::read_u16_be(original, rs16::kFirstBlockOffset + 11 * rs16::kBlockSize + 2);
    for (int b = 0; b < rs16::kBlocks; ++b)
      EXPECT_EQ(rs16::read_u16_be(all[i].payload, rs16::kFirstBlockOffset + b * rs16::kBlockSize + 2), *held) << i;
    ++stalled;
  }
  EXPECT_EQ(stalled, c.lidar_stalled);
  EXPECT_GE(stalled, 416u);  // 0.5 s of 1.2 ms packets
}

TEST_F(FaultInjector, ASecondLidarSendsTheStreamFromEarlierFasterAndRestampedFromAnotherHost) {
  FaultPlan plan;
  plan.second_lidar = SecondLidar{0.6, 0.6};  // the stream from 0 s on, 1.5x as fast: 0.9 s of it by the end
  const FaultCounts c = inject(plan);
  const auto all = read_lidar(out() / kLidarPcapName);
  std::uint64_t second = 0;
  std::int64_t previous_ns = 0;
  for (const auto& d : all) {
    EXPECT_GE(d.t_ns, previous_ns);  // merged in arrival order
    previous_ns = d.t_ns;
    if (d.src_ip == kLidarIp) continue;
    EXPECT_EQ(d.src_ip, kForeignLidarIp);
    EXPECT_GE(d.t_ns, kStartNs + 600'000'000);
    if (d.dst_port == 6699) {
      // Packet id was recorded at kStartNs + id * period; it arrives 0.6 s + that / 1.5 later, restamped.
      const int id = packet_id(d.payload);
      const std::int64_t recorded_ns = kStartNs + id * kMsopPeriodNs;
      EXPECT_NEAR(static_cast<double>(d.t_ns - kStartNs),
                  600e6 + static_cast<double>(recorded_ns - kStartNs) / kSecondLidarSpeedup, 1.0);
      EXPECT_EQ(header_time_ns(d.payload) - (recorded_ns - 1'000'000), d.t_ns - recorded_ns);
    }
    ++second;
  }
  EXPECT_EQ(second, c.lidar_second_sender);
  EXPECT_NEAR(static_cast<double>(second), 0.6 * kSecondLidarSpeedup / 1.2e-3, 10.0);  // MSOP, and a DIFOP or so
}

TEST_F(FaultInjector, ADifopChangeSteepensTheAnglesOfTheDifopsFromItsMomentOn) {
  FaultPlan plan;
  plan.difop_change_at_s = 0.5;
  const FaultCounts c = inject(plan);
  std::uint64_t changed = 0;
  for (const auto& d : read_lidar(out() / kLidarPcapName)) {
    if (d.dst_port != 7788) continue;
    rs16::DifopInfo info;
    ASSERT_EQ(rs16::decode_difop(d.payload, info), rs16::PacketError::None);
    const bool after = d.t_ns >= kStartNs + 500'000'000;
    EXPECT_NEAR(info.data.vertical_angles_deg[0], -15.0 * (after ? kRecalibratedAngleScale : 1.0), 1e-3);
    changed += after;
  }
  EXPECT_EQ(changed, c.difop_recalibrated);
  EXPECT_GE(changed, 5u);
}

TEST_F(FaultInjector, LateDatagramsKeepTheirOrderAndBytesAndArriveNoEarlier) {
  FaultPlan plan;
  plan.lidar_delay_s = 0.005;
  const FaultCounts c = inject(plan);
  const auto before = read_lidar(run_ / kLidarPcapName);
  const auto after = read_lidar(out() / kLidarPcapName);
  ASSERT_EQ(after.size(), before.size());
  double sum_s = 0.0, max_s = 0.0;
  for (std::size_t i = 0; i < after.size(); ++i) {
    EXPECT_EQ(after[i].payload, before[i].payload) << i;
    ASSERT_GE(after[i].t_ns, before[i].t_ns) << i;
    if (i > 0) {
      ASSERT_GE(after[i].t_ns, after[i - 1].t_ns) << i;
    }
    const double delay_s = static_cast<double>(after[i].t_ns - before[i].t_ns) * 1e-9;
    sum_s += delay_s;
    max_s = std::max(max_s, delay_s);
  }
  EXPECT_EQ(c.lidar_delayed, after.size());
  EXPECT_NEAR(c.lidar_mean_delay_s, sum_s / static_cast<double>(after.size()), 1e-9);
  EXPECT_DOUBLE_EQ(c.lidar_max_delay_s, max_s);
  // Held back behind slower ones, datagrams are later than the 5 ms mean hold.
  EXPECT_GT(c.lidar_mean_delay_s, 0.005);
  EXPECT_LT(c.lidar_mean_delay_s, 0.05);
  EXPECT_EQ(slurp(out() / kImuPcapName), slurp(run_ / kImuPcapName));
  const FaultCounts again = inject(plan, "again");
  EXPECT_EQ(slurp(out("again") / kLidarPcapName), slurp(out() / kLidarPcapName));
  EXPECT_EQ(again.lidar_stalls, c.lidar_stalls);
}

TEST_F(FaultInjector, BadPlansAndFoldersAreRefusedWithTheirName) {
  FaultPlan plan;
  plan.dup_lidar = 1.5;
  EXPECT_THROW(
      try { inject(plan); } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("--dup-lidar"), std::string::npos);
        throw;
      },
      std::invalid_argument);
  plan = {};
  plan.imu_gap = FaultWindow{1.0, 0.0};
  EXPECT_THROW(inject(plan), std::invalid_argument);
  plan = {};
  plan.lidar_delay_s = -0.001;
  EXPECT_THROW(inject(plan), std::invalid_argument);
  EXPECT_THROW(inject_faults(run_, run_, {}), std::invalid_argument);
  EXPECT_THROW(inject_faults(dir_.path() / "nothing", out(), {}), std::invalid_argument);
  EXPECT_THROW(parse_fault_window("--lidar-gap", "1"), std::invalid_argument);
  EXPECT_THROW(parse_fault_window("--lidar-gap", "1,x"), std::invalid_argument);
  EXPECT_THROW(parse_clock_jump("--lidar-clock-jump", ",5"), std::invalid_argument);
  const ClockJump j = parse_clock_jump("--lidar-clock-jump", "2.5,-5");
  EXPECT_DOUBLE_EQ(j.at_s, 2.5);
  EXPECT_DOUBLE_EQ(j.jump_s, -5.0);
}

}  // namespace
}  // namespace tumble::sim
