#include "drivers/rs16/scan_assembler.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "drivers/rs16/decoder.hpp"
#include "test/drivers/rs16/packet_stream.hpp"

namespace tumble::rs16 {
namespace {

struct ScanSeen {
  std::uint64_t index;
  std::uint32_t missing;
  bool by_gap;
  std::vector<LidarPoint> points;
};

// Decodes the stream's packets (those not in skip) into an assembler.
class Harness {
 public:
  explicit Harness(double split_deg = 0.0)
      : assembler_({split_deg}, [this](Scan& scan, const ScanReport& report) {
          scans.push_back({scan.index, scan.missing_packets, report.ended_by_gap, scan.points});
        }) {}

  void feed(const test::StreamSpec& spec, std::int64_t index) {
    DecodedPacket packet;
    ASSERT_TRUE(decoder_.decode_msop(encode_msop(test::stream_packet(spec, index)), 0.0, packet, stats));
    assembler_.add(packet, stats);
  }
  void feed_range(const test::StreamSpec& spec, std::int64_t from, std::int64_t to, const std::set<std::int64_t>& skip = {}) {
    for (std::int64_t i = from; i < to; ++i)
      if (!skip.contains(i)) feed(spec, i);
  }

  std::vector<ScanSeen> scans;
  DecoderStats stats;

 private:
  Decoder decoder_;
  ScanAssembler assembler_;
};

// Block azimuths of a scan's points, in order.
double first_azimuth(const ScanSeen& s) { return s.points.front().azimuth_deg; }

TEST(Rs16ScanAssembler, SplitsEachRevolutionAtTheSplitAzimuth) {
  test::StreamSpec spec;
  spec.start_azimuth_deg = 350.0;
  Harness h;
  h.feed_range(spec, 0, 220);  // crosses 0 deg after 25, 926 and 1827 of its 2640 blocks
  ASSERT_EQ(h.scans.size(), 3u);
  for (std::size_t i = 0; i < h.scans.size(); ++i) {
    const ScanSeen& s = h.scans[i];
    EXPECT_EQ(s.index, i);
    EXPECT_EQ(s.missing, 0u);
    EXPECT_FALSE(s.by_gap);
    for (std::size_t k = 1; k < s.points.size(); ++k) ASSERT_GE(s.points[k].t_s, s.points[k - 1].t_s);
  }
  // The first scan starts with the stream; later ones at the first block at or past 0 deg.
  EXPECT_NEAR(first_azimuth(h.scans[0]), 350.0, 1e-3);
  for (std::size_t i = 1; i < h.scans.size(); ++i) {
    EXPECT_LT(first_azimuth(h.scans[i]), test::block_step_deg(spec) + 1e-3);
    // A revolution is 900.9 blocks of 32 returns.
    EXPECT_TRUE(h.scans[i].points.size() == 900u * 32 || h.scans[i].points.size() == 901u * 32);
  }
  EXPECT_EQ(h.stats.scans, 3u);
  EXPECT_EQ(h.stats.missing_packets, 0u);
}

TEST(Rs16ScanAssembler, SplitAzimuthIsConfigurable) {
  test::StreamSpec spec;
  Harness h(123.45);
  h.feed_range(spec, 0, 200);
  ASSERT_GE(h.scans.size(), 2u);
  for (std::size_t i = 1; i < h.scans.size(); ++i) {
    EXPECT_GE(first_azimuth(h.scans[i]), 123.45);
    EXPECT_LT(first_azimuth(h.scans[i]), 123.45 + test::block_step_deg(spec));
    EXPECT_LT(h.scans[i - 1].points.back().azimuth_deg, 123.45 + test::block_step_deg(spec));
  }
  EXPECT_THROW(ScanAssembler({360.0}, nullptr), std::invalid_argument);
  EXPECT_THROW(ScanAssembler({-0.5}, nullptr), std::invalid_argument);
}

TEST(Rs16ScanAssembler, CountsMissingPacketsFromAzimuthJumps) {
  test::StreamSpec spec;
  spec.start_azimuth_deg = 10.0;
  Harness h;
  h.feed_range(spec, 0, 160, {20, 21, 22, 100});
  EXPECT_EQ(h.stats.missing_packets, 4u);
  ASSERT_EQ(h.scans.size(), 2u);
  EXPECT_EQ(h.scans[0].missing, 3u);
  EXPECT_EQ(h.scans[1].missing, 1u);
  EXPECT_EQ(h.stats.time_gaps, 0u);
}

TEST(Rs16ScanAssembler, SplitsEvenWhenThePacketsAroundTheSplitAreLost) {
  test::StreamSpec spec;
  spec.start_azimuth_deg = 300.0;  // 0 deg is crossed in packet ~12.5
  Harness h;
  h.feed_range(spec, 0, 80, {11, 12, 13});
  ASSERT_EQ(h.scans.size(), 1u);
  EXPECT_FALSE(h.scans[0].by_gap);
  EXPECT_NEAR(h.scans[0].points.back().azimuth_deg, 300.0 + 11 * 12 * test::block_step_deg(spec), 1.0);
  EXPECT_EQ(h.stats.missing_packets, 3u);
}

TEST(Rs16ScanAssembler, AGapOfARevolutionEndsTheScanInsteadOfMerging) {
  test::StreamSpec spec;
  spec.start_azimuth_deg = 10.0;
  Harness h;
  std::set<std::int64_t> lost;
  for (std::int64_t i = 20; i < 100; ++i) lost.insert(i);  // 80 packets > 75 per revolution
  h.feed_range(spec, 0, 180, lost);
  ASSERT_GE(h.scans.size(), 2u);
  EXPECT_TRUE(h.scans[0].by_gap);
  EXPECT_EQ(h.scans[0].points.size(), 20u * 384);
  EXPECT_EQ(h.stats.time_gaps, 1u);
  EXPECT_EQ(h.stats.missing_packets, 80u);
  // The next scan starts fresh with packet 100 and is cut at 0 deg as usual.
  EXPECT_FALSE(h.scans[1].by_gap);
  EXPECT_NEAR(h.scans[1].points.front().t_s - h.scans[0].points.back().t_s, 81 * 1332e-6 - 1318.5e-6, 1e-6);
  EXPECT_EQ(h.scans[1].missing, 0u);
}

TEST(Rs16ScanAssembler, TimeGoingBackEndsTheScan) {
  test::StreamSpec spec;
  Harness h;
  h.feed_range(spec, 100, 110);
  h.feed_range(spec, 50, 52);
  ASSERT_EQ(h.scans.size(), 1u);
  EXPECT_TRUE(h.scans[0].by_gap);
  EXPECT_EQ(h.scans[0].points.size(), 10u * 384);
  EXPECT_EQ(h.stats.time_gaps, 1u);
}

TEST(Rs16ScanAssembler, AzimuthWobbleBackwardsDoesNotSplit) {
  Harness h;
  Decoder decoder;
  test::StreamSpec spec;
  spec.start_azimuth_deg = 100.0;
  MsopPacketData p = test::stream_packet(spec, 3);
  p.blocks[0].azimuth_deg = test::stream_packet(spec, 2).blocks[11].azimuth_deg - 0.01;
  DecodedPacket packet;
  ASSERT_TRUE(decoder.decode_msop(encode_msop(p), 0.0, packet, h.stats));
  ScanAssembler assembler({0.0}, [&](Scan&, const ScanReport&) { FAIL() << "split on a wobble"; });
  DecodedPacket previous;
  ASSERT_TRUE(decoder.decode_msop(encode_msop(test::stream_packet(spec, 2)), 0.0, previous, h.stats));
  assembler.add(previous, h.stats);
  assembler.add(packet, h.stats);
  EXPECT_EQ(assembler.pending_points(), 2u * 384);
  EXPECT_EQ(h.stats.missing_packets, 0u);
}

TEST(Rs16ScanAssembler, HandlerMaySwapThePointsOut) {
  test::StreamSpec spec;
  std::vector<std::vector<LidarPoint>> kept;
  ScanAssembler assembler({0.0}, [&](Scan& scan, const ScanReport&) {
    std::vector<LidarPoint> mine;
    scan.points.swap(mine);
    kept.push_back(std::move(mine));
  });
  Decoder decoder;
  DecoderStats stats;
  DecodedPacket packet;
  for (int i = 0; i < 160; ++i) {
    ASSERT_TRUE(decoder.decode_msop(encode_msop(test::stream_packet(spec, i)), 0.0, packet, stats));
    assembler.add(packet, stats);
  }
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[0].size() % 32, 0u);
  EXPECT_GT(kept[1].size(), 28000u);
}

}  // namespace
}  // namespace tumble::rs16
