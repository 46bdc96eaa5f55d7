// The simulated RS-16 against the project's own decoder: the decoder must put
// every return back where the simulator cast it, and motion must skew a scan
// the way de-skewing undoes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "drivers/pcap/pcap_file.hpp"
#include "drivers/pcap/udp_frame.hpp"
#include "drivers/rs16/decoder.hpp"
#include "drivers/rs16/difop_decode.hpp"
#include "drivers/rs16/laser_geometry.hpp"
#include "drivers/rs16/msop_decode.hpp"
#include "drivers/rs16/pcap_source.hpp"
#include "test/tools/sim/sensor_test_support.hpp"
#include "tools/sim/lidar_stream.hpp"
#include "tools/sim/run_writer.hpp"
#include "tools/sim/scene_load.hpp"

namespace tumble::sim {
namespace {

using test::BoxRoom;
using test::SpinMotion;
using test::TempDir;

constexpr std::int64_t kEpochNs = 1'622'030'400'000'000'000;  // 2021-05-26T12:00:00Z

struct DecodedPoint {
  double t_s;  // run time
  Eigen::Vector3d p_l;
  float intensity;
};

// Every point of a stream, as the driver decodes it: written to a lidar pcap
// as tcpdump would hold it, replayed by the driver's pcap source and decoded
// (synced clock, DIFOP angles).
std::vector<DecodedPoint> decode_all(LidarStream& stream, rs16::DecoderStats& stats) {
  TempDir dir;
  const auto path = (dir.path() / "lidar.pcap").string();
  {
    pcap::Writer writer(path, pcap::kLinkEthernet);
    LidarDatagram d;
    while (stream.next(d)) {
      writer.write(kEpochNs + d.arrival_ns,
                   pcap::make_udp_ethernet_frame(kLidarIp, kHostIp, d.dst_port, d.dst_port, d.payload));
    }
  }
  rs16::PcapSource source(path, rs16::SourceConfig{});
  rs16::DecoderConfig config;
  config.wait_for_difop = true;
  rs16::Decoder decoder(config);
  rs16::DecodedPacket packet;
  std::vector<DecodedPoint> points;
  while (const auto d = source.next()) {
    if (d->kind == rs16::PacketKind::Difop) {
      decoder.decode_difop(d->payload, stats);
      continue;
    }
    if (!decoder.decode_msop(d->payload, d->arrival_s, packet, stats)) continue;
    for (const LidarPoint& p : packet.all_points()) {
      points.push_back({p.t_s - static_cast<double>(kEpochNs) * 1e-9, Eigen::Vector3d(p.x_m, p.y_m, p.z_m), p.intensity});
    }
  }
  EXPECT_EQ(source.stats().msop, stream.msop_count());
  EXPECT_EQ(source.stats().difop, stream.difop_count());
  return points;
}

class LidarModelTest : public ::testing::Test {
 protected:
  void SetUp() override { scene_ = load_scene(room_.write(dir_.path()).string()); }

  // Streams stay short: under ASan + coverage (Debug) a ray costs ~0.5 ms.
  LidarStream stream(const Motion& motion, const LidarConfig& config, double duration_s,
                     const LidarLinkConfig& link = {}, double azimuth_at_zero_deg = 123.4) {
    LidarTiming timing;
    timing.epoch_ns = kEpochNs;
    timing.first_packet_ns = 317'000;
    timing.first_difop_ns = 0;  // the decoder has the calibration from the first packet on
    timing.azimuth_at_zero_deg = azimuth_at_zero_deg;
    return LidarStream(config, unit_, link, timing, scene_, motion, 42, duration_s);
  }

  TempDir dir_;
  BoxRoom room_;
  Scene scene_;
  LidarUnit unit_ = make_lidar_unit(5, LidarConfig{});
};

TEST(LidarBeam, IsExactlyTheDecodersGeometry) {
  SensorRng rng(1, "test");
  for (int i = 0; i < 1000; ++i) {
    const double azimuth = rng.uniform(0.0, 360.0), vertical = rng.uniform(-16.0, 16.0), d = rng.uniform(0.4, 150.0);
    const Beam beam = rs16_beam(azimuth, vertical);
    const double a = azimuth * std::numbers::pi / 180.0, w = vertical * std::numbers::pi / 180.0;
    const rs16::PointXyz q = rs16::to_cartesian(d, std::cos(w), std::sin(w), std::cos(a), std::sin(a));
    const Eigen::Vector3d p = beam.origin_l + d * beam.direction_l;
    EXPECT_NEAR(beam.direction_l.norm(), 1.0, 1e-15);
    EXPECT_NEAR((p - Eigen::Vector3d(q.x_m, q.y_m, q.z_m)).norm(), 0.0, 1e-12);
  }
}

TEST(LidarUnitCalibration, StaysNearTheDesignAnglesOnTheDifopGrid) {
  const LidarUnit a = make_lidar_unit(3, LidarConfig{}), b = make_lidar_unit(3, LidarConfig{}), c = make_lidar_unit(4, LidarConfig{});
  EXPECT_EQ(a.vertical_angles_deg, b.vertical_angles_deg);
  EXPECT_NE(a.vertical_angles_deg, c.vertical_angles_deg);
  int off_design = 0;
  for (int i = 0; i < 16; ++i) {
    const double angle = a.vertical_angles_deg[static_cast<std::size_t>(i)];
    EXPECT_LE(std::abs(angle - rs16::kDesignVerticalAnglesDeg[static_cast<std::size_t>(i)]), 0.3 + 1e-9);
    EXPECT_NEAR(angle * 1e4, std::round(angle * 1e4), 1e-6);
    off_design += angle != rs16::kDesignVerticalAnglesDeg[static_cast<std::size_t>(i)];
  }
  EXPECT_GT(off_design, 12);
}

TEST_F(LidarModelTest, DifopCarriesTheUnitAndTheMotorSpeed) {
  const SpinMotion still({0, 0, 1}, 0.0, 0.025);
  LidarConfig config;
  config.rpm = 1200;
  LidarLinkConfig link;
  link.difop_period_s = 0.01;  // short, so the test casts few rays
  LidarStream s = stream(still, config, 0.025, link);
  LidarDatagram d;
  int difops = 0;
  while (s.next(d)) {
    if (!d.is_difop) continue;
    ++difops;
    rs16::DifopInfo info;
    ASSERT_EQ(rs16::decode_difop(d.payload, info), rs16::PacketError::None);
    EXPECT_TRUE(info.angles_calibrated);
    EXPECT_EQ(info.data.motor_rpm, 1200);
    EXPECT_EQ(info.data.serial, unit_.serial);
    EXPECT_DOUBLE_EQ(info.resolution_m, 0.005);
    for (std::size_t i = 0; i < 16; ++i) EXPECT_NEAR(info.data.vertical_angles_deg[i], unit_.vertical_angles_deg[i], 1e-9);
    EXPECT_EQ(info.data.utc_time_ns, kEpochNs + (difops - 1) * 10'000'000LL);
  }
  EXPECT_EQ(difops, 3);  // at 0, 10 and 20 ms
}

TEST_F(LidarModelTest, PacketsFollowTheFiringPatternAndArriveAfterTheirLastFiring) {
  const SpinMotion still({0, 0, 1}, 0.0, 0.02);
  LidarStream s = stream(still, LidarConfig{}, 0.02);
  LidarDatagram d;
  std::int64_t previous_arrival = -1, previous_header = 0;
  double previous_azimuth = -1;
  int msops = 0;
  while (s.next(d)) {
    EXPECT_GT(d.arrival_ns, previous_arrival);
    previous_arrival = d.arrival_ns;
    if (d.is_difop) continue;
    rs16::MsopHeader h;
    ASSERT_EQ(rs16::parse_msop_header(d.payload, h), rs16::PacketError::None);
    EXPECT_EQ(h.valid_blocks, 12);
    const std::int64_t first_firing_ns = h.utc_time_ns - kEpochNs;
    EXPECT_EQ(first_firing_ns, 317'000 + msops * kRs16PacketPeriodNs);
    // Leaves after the last firing (1318.5 us later) plus the network.
    EXPECT_GE(d.arrival_ns - first_firing_ns, kRs16PacketSpanNs + 300'000);
    if (msops > 0) {
      EXPECT_EQ(h.utc_time_ns - previous_header, 1'332'000);
    }
    previous_header = h.utc_time_ns;
    // 600 rpm: 0.0666 deg per 111 us block.
    rs16::MsopPacketData fields;
    ASSERT_EQ(rs16::decode_msop_fields(d.payload, 0.005, fields, h), rs16::PacketError::None);
    if (previous_azimuth >= 0) {
      const double step = std::fmod(fields.blocks[0].azimuth_deg - previous_azimuth + 360.0, 360.0);
      EXPECT_NEAR(step, 12 * 3600.0 * 111e-6, 0.011);
    }
    previous_azimuth = fields.blocks[0].azimuth_deg;
    ++msops;
  }
  EXPECT_EQ(msops, 14);  // (20 ms - 0.317 ms - 1.3185 ms) / 1.332 ms, rounded up
}

TEST_F(LidarModelTest, StaticNoiselessScanDecodesOntoTheSurfaces) {
  const Eigen::Vector3d centre(0.5, -0.3, 1.1);
  const SpinMotion still(centre, 0.0, 0.015);
  LidarConfig config;
  config.range_noise_m = 0.0;
  config.dropout_probability = 0.0;
  // 54 deg of azimuth around -x: head-on to the x = -5 wall and grazing the floor.
  LidarStream s = stream(still, config, 0.015, {}, 153.0);
  rs16::DecoderStats stats;
  const auto points = decode_all(s, stats);
  // A closed room: every firing returns (no drops besides min range).
  EXPECT_EQ(stats.dropped.zero_range, 0u);
  EXPECT_EQ(points.size(), s.msop_count() * 384);
  double worst = 0;
  float max_intensity = 0, min_intensity = 255;
  for (const auto& p : points) {
    worst = std::max(worst, room_.distance(centre + p.p_l));
    max_intensity = std::max(max_intensity, p.intensity);
    min_intensity = std::min(min_intensity, p.intensity);
  }
  // Only the 0.5 cm range quantisation is left.
  EXPECT_LT(worst, 0.0025 + 1e-6);
  // Reflectivity 0.6: 60 head-on, less at grazing incidence.
  EXPECT_EQ(max_intensity, 60.0f);
  EXPECT_LT(min_intensity, 30.0f);
}

double rms_distance(const std::vector<DecodedPoint>& points, const BoxRoom& room, const Motion& motion, bool deskew) {
  double sum = 0;
  for (const auto& p : points) {
    // Without de-skewing, the whole revolution is taken at its start pose.
    const double scan_start_s = std::floor(p.t_s / 0.1) * 0.1;
    const Eigen::Isometry3d T = motion.at(deskew ? p.t_s : scan_start_s).T_wb;
    const double d = room.distance(T * p.p_l);
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(points.size()));
}

TEST_F(LidarModelTest, SpinAtTenRadPerSecondIsUndoneByDeskewingOnly) {
  // 30 ms: the head turns 108 deg while the body turns 0.3 rad.
  const SpinMotion spin({0.5, -0.3, 1.1}, 10.0, 0.03);
  LidarConfig config;  // 2 cm range noise
  config.dropout_probability = 0.0;
  LidarStream s = stream(spin, config, 0.03);
  rs16::DecoderStats stats;
  const auto points = decode_all(s, stats);
  ASSERT_GT(points.size(), 7000u);
  const double deskewed = rms_distance(points, room_, spin, true);
  const double raw = rms_distance(points, room_, spin, false);
  // Noise is along the beam; the distance to the surface is its normal part,
  // plus the quantisation.
  EXPECT_LT(deskewed, 1.1 * config.range_noise_m);
  EXPECT_GT(deskewed, 0.3 * config.range_noise_m);
  EXPECT_GT(raw, 5.0 * config.range_noise_m);
}

TEST_F(LidarModelTest, RangeLimitsAndDropoutsGiveNoReturn) {
  const SpinMotion still({0.5, -0.3, 1.1}, 0.0, 0.006);
  LidarConfig near_only;
  near_only.max_range_m = 2.0;
  LidarStream s = stream(still, near_only, 0.006);
  rs16::DecoderStats stats;
  for (const auto& p : decode_all(s, stats)) EXPECT_LE(p.p_l.norm(), 2.0 + 0.04);
  EXPECT_GT(stats.dropped.zero_range, 0u);

  LidarConfig all_dropped;
  all_dropped.dropout_probability = 1.0;
  LidarStream dropped = stream(still, all_dropped, 0.006);
  rs16::DecoderStats none;
  EXPECT_TRUE(decode_all(dropped, none).empty());
}

TEST(BlockAzimuths, AdvanceWithTimeAtTheMotorRateAndWrap) {
  for (const int rpm : {300, 600, 1200}) {
    const double deg_per_s = rpm * 6.0;
    const auto blocks = block_azimuths_centideg(359.9, deg_per_s, 0);
    for (int b = 0; b < 12; ++b) {
      const double expected = std::fmod(std::round(std::fmod(359.9 + deg_per_s * 111e-6 * b, 360.0) * 100.0), 36000.0);
      EXPECT_EQ(blocks[static_cast<std::size_t>(b)], expected) << rpm << " rpm, block " << b;
    }
    // The decoder's interpolation inside a block: channel 16 is half a block on.
    const double step = rpm * 6.0 * 111e-6;
    EXPECT_NEAR(std::fmod(channel_azimuth_deg(blocks, 3, 16, rpm) - blocks[3] / 100.0 + 360.0, 360.0), step / 2, 0.006);
  }
}

}  // namespace
}  // namespace tumble::sim
