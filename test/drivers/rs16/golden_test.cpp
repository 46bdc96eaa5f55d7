// Conformance with RoboSense's own driver on the synthetic capture: the same
// points (xyz within 2 mm: the vendor rounds angles to 0.01 deg; time within
// 1 us), no-return slots dropped and counted, and scans of the same sizes at
// the same split points. The vendor's numbers are read from its file here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "drivers/rs16/decoder.hpp"
#include "drivers/rs16/driver.hpp"
#include "drivers/rs16/pcap_source.hpp"
#include "test/drivers/rs16/vendor_decode.hpp"
#include "test/fixtures.hpp"

namespace tumble::rs16 {
namespace {

constexpr double kXyzTolerance_m = 0.002;
constexpr double kTimeTolerance_s = 1e-6;
const char* const kPcap = "rs16/rs16_synthetic.pcap";
const char* const kVendor = "rs16/rs16_synthetic.vendor-decode.txt";

// The vendor driver waits for the first DIFOP; so do we here.
DecoderConfig vendor_like_config() {
  DecoderConfig c;
  c.wait_for_difop = true;
  return c;
}

TEST(Rs16Golden, FirstDecodedPacketMatchesVendorPoints) {
  TUMBLE_REQUIRE_FIXTURE(kPcap);
  TUMBLE_REQUIRE_FIXTURE(kVendor);
  const auto vendor = test::read_vendor_decode(tumble::test::fixture_path(kVendor).string());
  PcapSource source(tumble::test::fixture_path(kPcap).string(), {});
  Decoder decoder(vendor_like_config());
  DecoderStats stats;
  DecodedPacket packet;
  bool decoded = false;
  while (!decoded) {
    const auto d = source.next();
    ASSERT_TRUE(d) << "no MSOP packet after a DIFOP in the capture";
    if (d->kind == PacketKind::Difop)
      decoder.decode_difop(d->payload, stats);
    else
      decoded = decoder.decode_msop(d->payload, d->arrival_s, packet, stats);
  }
  EXPECT_EQ(stats.msop_before_difop, 1u);
  EXPECT_EQ(decoder.lasers().source, AngleSource::Difop);

  std::array<int, 16> laser_of_ring{};
  for (int laser = 0; laser < 16; ++laser) laser_of_ring[vendor.ring_of_laser[laser]] = laser;

  int vendor_no_returns = 0;
  for (const auto& v : vendor.points) {
    const int block = v.index / 32;
    const int laser = laser_of_ring[v.ring];
    const auto block_points = packet.block_points(block);
    const auto match = std::find_if(block_points.begin(), block_points.end(), [&](const LidarPoint& p) {
      return p.laser == laser && std::abs(p.t_s - v.t_s) < kTimeTolerance_s;
    });
    if (std::isnan(v.x)) {
      ++vendor_no_returns;
      EXPECT_EQ(match, block_points.end()) << "vendor point " << v.index << " has no return, we made a point";
      continue;
    }
    ASSERT_NE(match, block_points.end()) << "no point for vendor point " << v.index;
    EXPECT_NEAR(match->x_m, v.x, kXyzTolerance_m) << "vendor point " << v.index;
    EXPECT_NEAR(match->y_m, v.y, kXyzTolerance_m) << "vendor point " << v.index;
    EXPECT_NEAR(match->z_m, v.z, kXyzTolerance_m) << "vendor point " << v.index;
    EXPECT_EQ(match->intensity, v.intensity) << "vendor point " << v.index;
    EXPECT_EQ(match->return_index, 0);
  }
  ASSERT_GT(vendor_no_returns, 0) << "the listed points should include a no-return slot";
  EXPECT_GE(stats.dropped.zero_range, static_cast<std::uint64_t>(vendor_no_returns));
  EXPECT_EQ(stats.dropped.total(), stats.dropped.zero_range);
  EXPECT_EQ(packet.all_points().size() + stats.dropped.zero_range, 384u);

  // The packet's last slot (block 11, channel 31) fires when the vendor says.
  ASSERT_EQ(vendor.last_point_index, 383);
  const LidarPoint& last = packet.all_points().back();
  EXPECT_EQ(last.laser, 15);
  EXPECT_NEAR(last.t_s, vendor.last_point_t_s, kTimeTolerance_s);
}

TEST(Rs16Golden, VerticalAnglesKeepFullDifopPrecision) {
  TUMBLE_REQUIRE_FIXTURE(kPcap);
  TUMBLE_REQUIRE_FIXTURE(kVendor);
  const auto vendor = test::read_vendor_decode(tumble::test::fixture_path(kVendor).string());
  PcapSource source(tumble::test::fixture_path(kPcap).string(), {});
  Decoder decoder;
  DecoderStats stats;
  while (const auto d = source.next()) {
    if (d->kind == PacketKind::Difop) {
      decoder.decode_difop(d->payload, stats);
      break;
    }
  }
  ASSERT_EQ(decoder.lasers().source, AngleSource::Difop);
  bool finer_than_vendor = false;
  for (int laser = 0; laser < 16; ++laser) {
    const double ours = decoder.lasers().vertical_deg[laser];
    // The vendor truncates to 0.01 deg toward zero.
    EXPECT_NEAR(std::trunc(ours * 100.0) / 100.0, vendor.vertical_angle_deg[laser], 1e-9) << "laser " << laser;
    finer_than_vendor = finer_than_vendor || std::abs(ours - vendor.vertical_angle_deg[laser]) > 1e-6;
  }
  EXPECT_TRUE(finer_than_vendor);
  // The vendor's rings number the lasers by rising vertical angle.
  for (int a = 0; a < 16; ++a) {
    for (int b = 0; b < 16; ++b) {
      if (vendor.ring_of_laser[a] < vendor.ring_of_laser[b]) {
        EXPECT_LT(decoder.lasers().vertical_deg[a], decoder.lasers().vertical_deg[b]);
      }
    }
  }
}

TEST(Rs16Golden, ScansSplitWhereVendorSplits) {
  TUMBLE_REQUIRE_FIXTURE(kPcap);
  TUMBLE_REQUIRE_FIXTURE(kVendor);
  const auto vendor = test::read_vendor_decode(tumble::test::fixture_path(kVendor).string());
  struct Seen {
    std::size_t returns;
    double last_t_s;
    std::uint64_t index;
    std::uint32_t missing;
  };
  std::vector<Seen> scans;
  DriverConfig config;
  config.decoder = vendor_like_config();
  Driver driver(config, [&](Scan& scan, const ScanReport& report) {
    scans.push_back({scan.points.size() + report.returns_dropped, scan.points.back().t_s, scan.index,
                     scan.missing_packets});
  });
  PcapSource source(tumble::test::fixture_path(kPcap).string(), {});
  while (const auto d = source.next()) driver.on_datagram(*d);

  EXPECT_FALSE(source.truncated());
  EXPECT_EQ(source.stats().msop, static_cast<std::uint64_t>(vendor.msop_packets));
  ASSERT_EQ(scans.size(), static_cast<std::size_t>(vendor.frames));
  ASSERT_EQ(vendor.splits.size(), scans.size());
  for (std::size_t i = 0; i < scans.size(); ++i) {
    EXPECT_EQ(scans[i].index, static_cast<std::uint64_t>(vendor.splits[i].frame));
    EXPECT_EQ(scans[i].returns, static_cast<std::size_t>(vendor.splits[i].points)) << "scan " << i;
    EXPECT_NEAR(scans[i].last_t_s, vendor.splits[i].cloud_t_s, kTimeTolerance_s) << "scan " << i;
    EXPECT_EQ(scans[i].missing, 0u);
  }
  const DecoderStats& s = driver.stats();
  EXPECT_EQ(s.scans, scans.size());
  EXPECT_EQ(s.missing_packets, 0u);
  EXPECT_EQ(s.time_gaps, 0u);
  EXPECT_EQ(s.bad_msop.total(), 0u);
  EXPECT_EQ(s.bad_difop.total(), 0u);
  EXPECT_EQ(s.msop_packets + s.msop_before_difop, source.stats().msop);
  EXPECT_EQ(s.difop_packets, source.stats().difop);
  EXPECT_GT(s.dropped.zero_range, 0u);
  EXPECT_EQ(s.points + s.dropped.total(), s.msop_packets * 384);
}

}  // namespace
}  // namespace tumble::rs16
