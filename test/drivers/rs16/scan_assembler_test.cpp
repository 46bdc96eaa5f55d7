#include "drivers/rs16/scan_assembler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
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

bool same_points(const std::vector<LidarPoint>& a, const std::vector<LidarPoint>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].t_s != b[i].t_s || a[i].azimuth_deg != b[i].azimuth_deg || a[i].laser != b[i].laser) return false;
  }
  return true;
}

// The scans of packets [0, 160) fed in order, to compare a disordered feed with.
std::vector<ScanSeen> clean_scans(const test::StreamSpec& spec);

// Decodes the stream's packets (those not in skip) into an assembler.
class Harness {
 public:
  explicit Harness(double split_deg = 0.0)
      : assembler_({split_deg}, [this](Scan& scan, const ScanReport& report) {
          scans.push_back({scan.index, scan.missing_packets, report.ended_by_gap, scan.points});
          reports.push_back(report);
        }) {}

  void feed(const test::StreamSpec& spec, std::int64_t index) { feed_packet(test::stream_packet(spec, index)); }
  void feed_packet(const MsopPacketData& data) {
    DecodedPacket packet;
    ASSERT_TRUE(decoder_.decode_msop(encode_msop(data), 0.0, packet, stats));
    assembler_.add(packet, stats);
  }
  void feed_range(const test::StreamSpec& spec, std::int64_t from, std::int64_t to, const std::set<std::int64_t>& skip = {}) {
    for (std::int64_t i = from; i < to; ++i)
      if (!skip.contains(i)) feed(spec, i);
  }

  std::size_t assembler_points() const { return assembler_.pending_points(); }

  std::vector<ScanSeen> scans;
  std::vector<ScanReport> reports;
  DecoderStats stats;

 private:
  Decoder decoder_;
  ScanAssembler assembler_;
};

std::vector<ScanSeen> clean_scans(const test::StreamSpec& spec) {
  Harness h;
  h.feed_range(spec, 0, 160);
  return h.scans;
}

void expect_same_scans(const std::vector<ScanSeen>& got, const std::vector<ScanSeen>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(got[i].missing, 0u);
    EXPECT_FALSE(got[i].by_gap);
    EXPECT_TRUE(same_points(got[i].points, want[i].points));
  }
}

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

TEST(Rs16ScanAssembler, TimeGoingBackARevolutionOrMoreEndsTheScan) {
  test::StreamSpec spec;
  Harness h;
  h.feed_range(spec, 100, 110);
  h.feed_range(spec, 20, 22);  // 80 packets back: more than the 75 of a revolution
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

TEST(Rs16ScanAssembler, ExactDuplicatesAreDroppedAndCounted) {
  test::StreamSpec spec;
  spec.start_azimuth_deg = 10.0;
  Harness h;
  for (std::int64_t i = 0; i < 160; ++i) {
    h.feed(spec, i);
    if (i % 10 == 3) h.feed(spec, i);                  // right behind the original
    if (i % 10 == 7 && i >= 2) h.feed(spec, i - 2);    // two packets later
  }
  EXPECT_EQ(h.stats.duplicate_packets, 32u);
  EXPECT_EQ(h.stats.time_gaps, 0u);
  EXPECT_EQ(h.stats.missing_packets, 0u);
  EXPECT_EQ(h.stats.late_packets + h.stats.late_packets_dropped, 0u);
  expect_same_scans(h.scans, clean_scans(spec));
}

TEST(Rs16ScanAssembler, SwappedNeighboursGoIntoTheirScanInFiringOrder) {
  test::StreamSpec spec;
  spec.start_azimuth_deg = 10.0;
  Harness h;
  const std::set<std::int64_t> swapped{5, 30, 61, 90, 120};  // i arrives after i + 1
  for (std::int64_t i = 0; i < 160; ++i) {
    if (swapped.contains(i)) {
      h.feed(spec, i + 1);
      h.feed(spec, i);
      ++i;
    } else {
      h.feed(spec, i);
    }
  }
  EXPECT_EQ(h.stats.late_packets, swapped.size());
  EXPECT_EQ(h.stats.late_packets_dropped, 0u);
  EXPECT_EQ(h.stats.time_gaps, 0u);
  EXPECT_EQ(h.stats.missing_packets, 0u);
  expect_same_scans(h.scans, clean_scans(spec));
}

TEST(Rs16ScanAssembler, ALatePacketWhoseScanHasClosedIsDroppedNotASplit) {
  test::StreamSpec spec;
  spec.start_azimuth_deg = 300.0;  // 0 deg is crossed in packet ~12.5
  Harness h;
  h.feed_range(spec, 0, 11);
  h.feed_range(spec, 12, 14);  // the split: scan 0 is handed on
  h.feed(spec, 11);            // fired before the open scan began
  h.feed_range(spec, 14, 80);
  EXPECT_EQ(h.stats.late_packets_dropped, 1u);
  EXPECT_EQ(h.stats.late_packets, 0u);
  EXPECT_EQ(h.stats.time_gaps, 0u);
  EXPECT_EQ(h.stats.missing_packets, 1u);
  ASSERT_EQ(h.scans.size(), 1u);
  EXPECT_FALSE(h.scans[0].by_gap);
  EXPECT_EQ(h.scans[0].points.size(), 11u * 384 + 7u * 32);  // packets 0..10 and 12 up to the split
  EXPECT_EQ(h.scans[0].missing, 1u);
  EXPECT_GT(h.assembler_points(), 60u * 384);  // scan 1 goes on undisturbed
}

TEST(Rs16ScanAssembler, AScanCoveringLessThanTheMinimumTurnIsReportedShort) {
  test::StreamSpec spec;
  spec.start_azimuth_deg = 200.0;  // the first scan covers 160 deg only
  Harness h;
  std::set<std::int64_t> lost;
  for (std::int64_t i = 150; i < 180; ++i) lost.insert(i);  // 40 % of the third revolution
  h.feed_range(spec, 0, 250, lost);
  ASSERT_EQ(h.reports.size(), 3u);
  EXPECT_NEAR(h.reports[0].azimuth_coverage, 160.0 / 360.0, 0.01);
  EXPECT_TRUE(h.reports[0].short_coverage);
  EXPECT_NEAR(h.reports[1].azimuth_coverage, 1.0, 0.01);
  EXPECT_FALSE(h.reports[1].short_coverage);
  EXPECT_NEAR(h.reports[2].azimuth_coverage, 0.6, 0.02);
  EXPECT_TRUE(h.reports[2].short_coverage);
  EXPECT_EQ(h.stats.scans_short_coverage, 2u);
  EXPECT_THROW(ScanAssembler({0.0, 1.5}, nullptr), std::invalid_argument);
  EXPECT_THROW(ScanAssembler({0.0, -0.1}, nullptr), std::invalid_argument);
}

// The points of kMaxScanRevolutions at the slowest motor speed.
double max_scan_points(const test::StreamSpec& spec) {
  return kMaxScanRevolutions * kAzimuthUnitsPerTurn / nominal_block_step(kSlowestRpm, spec.mode) * kChannelsPerBlock;
}

// Packet index of the stream with the head stopped at 45 deg; its header
// time advances at time_scale of the real rate.
MsopPacketData stalled_packet(const test::StreamSpec& spec, std::int64_t index, double time_scale) {
  MsopPacketData p = test::stream_packet(spec, index);
  p.utc_time_ns = spec.start_ns + std::llround(index * packet_duration_s(spec.mode) * time_scale * 1e9);
  for (auto& block : p.blocks) block.azimuth_deg = 45.0;
  return p;
}

// The motor stalls with the lasers firing: 2 s of packets at one azimuth.
TEST(Rs16ScanAssembler, AStalledMotorsScanIsCutAtTheBoundInTimeAndFlagged) {
  test::StreamSpec spec;
  Harness h;
  h.feed_range(spec, 0, 100);
  const std::size_t turning = h.reports.size();
  std::size_t most_points = 0;
  for (std::int64_t i = 100; i < 1600; ++i) {
    h.feed_packet(stalled_packet(spec, i, 1.0));
    most_points = std::max(most_points, h.assembler_points());
  }
  EXPECT_LE(static_cast<double>(most_points), max_scan_points(spec));
  ASSERT_GE(h.reports.size(), turning + 6);  // 2 s at 0.3 s a cut scan
  for (std::size_t i = turning; i < h.reports.size(); ++i) {
    EXPECT_TRUE(h.reports[i].cut_at_bound) << i;
    if (i > turning) {  // the first holds the last turn
      EXPECT_TRUE(h.reports[i].short_coverage) << i;
    }
  }
  EXPECT_EQ(h.stats.scans_cut_at_bound, h.reports.size() - turning);
}

// A header clock that crawls (or a sender that floods) fills a scan faster
// than the motor turns: the points bound cuts it.
TEST(Rs16ScanAssembler, AScanThatFillsFasterThanTheMotorTurnsIsCutAtTheBoundInPoints) {
  test::StreamSpec spec;
  Harness h;
  std::size_t most_points = 0;
  for (std::int64_t i = 0; i < 3000; ++i) {
    h.feed_packet(stalled_packet(spec, i, 0.1));
    most_points = std::max(most_points, h.assembler_points());
  }
  EXPECT_LE(static_cast<double>(most_points), max_scan_points(spec));
  EXPECT_GE(h.stats.scans_cut_at_bound, 10u);  // 3000 packets of 384 points, about 86'000 a scan
}

// At 300 rpm while the decoder assumes its default 600 (no DIFOP yet).
TEST(Rs16ScanAssembler, AWholeRevolutionIsNeverCut) {
  test::StreamSpec spec;
  spec.rpm = kSlowestRpm;
  Harness h;
  h.feed_range(spec, 0, 2000);
  EXPECT_GE(h.reports.size(), 5u);
  EXPECT_EQ(h.stats.scans_cut_at_bound, 0u);
}

}  // namespace
}  // namespace tumble::rs16
