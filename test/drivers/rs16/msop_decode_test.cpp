#include "drivers/rs16/msop_decode.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "drivers/rs16/packet_layout.hpp"
#include "test/drivers/rs16/packet_stream.hpp"

namespace tumble::rs16 {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr std::int64_t kT0Ns = 1'704'067'200'000'000'000;
// Epoch seconds in a double resolve 0.24 us.
constexpr double kDecodeTimeTolerance_s = 5e-7;

struct Decoded {
  MsopHeader header;
  DecodedPacket packet;
  DroppedPoints dropped;
};

Decoded decode(const std::array<std::uint8_t, 1248>& bytes, const LaserTable& lasers, const PointSettings& settings = {}) {
  Decoded d;
  EXPECT_EQ(parse_msop_header(bytes, d.header), PacketError::None);
  decode_msop_points(bytes, d.header, d.header.utc_time_ns * 1e-9, lasers, settings, d.packet, d.dropped);
  return d;
}

LaserTable flat_lasers() {
  std::array<double, 16> flat{};
  return make_laser_table(flat, AngleSource::Config);
}

MsopPacketData packet_with_azimuths(double first_deg, double step_deg) {
  MsopPacketData p;
  p.utc_time_ns = kT0Ns;
  for (int b = 0; b < 12; ++b) {
    p.blocks[b].azimuth_deg = std::fmod(first_deg + step_deg * b, 360.0);
    for (int c = 0; c < 32; ++c) p.blocks[b].channels[c] = {10.0, static_cast<std::uint8_t>(c)};
  }
  return p;
}

TEST(Rs16MsopDecode, GeometryIsForwardLeftUpWithOpticalCentreOffset) {
  std::array<double, 16> angles{};
  angles[8] = 30.0;
  const LaserTable lasers = make_laser_table(angles, AngleSource::Config);
  for (const double azimuth_deg : {0.0, 90.0, 180.0, 270.0, 33.3}) {
    MsopPacketData p = packet_with_azimuths(azimuth_deg, 0.0);  // no turn: every point at the block azimuth
    const Decoded d = decode(encode_msop(p), lasers);
    const double a = azimuth_deg * kDegToRad;
    const LidarPoint& level = d.packet.points[0];  // laser 0, vertical 0
    EXPECT_NEAR(level.x_m, (10.0 + kOpticalCentreOffset_m) * std::cos(a), 1e-5);
    EXPECT_NEAR(level.y_m, -(10.0 + kOpticalCentreOffset_m) * std::sin(a), 1e-5);
    EXPECT_NEAR(level.z_m, 0.0, 1e-6);
    const LidarPoint& up = d.packet.points[8];  // laser 8, 30 deg up
    ASSERT_EQ(up.laser, 8);
    const double horizontal = 10.0 * std::cos(30.0 * kDegToRad) + kOpticalCentreOffset_m;
    EXPECT_NEAR(up.x_m, horizontal * std::cos(a), 1e-5);
    EXPECT_NEAR(up.y_m, -horizontal * std::sin(a), 1e-5);
    EXPECT_NEAR(up.z_m, 5.0, 1e-5);
  }
}

TEST(Rs16MsopDecode, PointTimesFollowTheFiringModel) {
  const Decoded d = decode(encode_msop(packet_with_azimuths(10.0, 0.4)), flat_lasers());
  ASSERT_EQ(d.packet.all_points().size(), 384u);
  const double t0 = kT0Ns * 1e-9;
  for (int b = 0; b < 12; ++b) {
    const auto points = d.packet.block_points(b);
    ASSERT_EQ(points.size(), 32u);
    for (int c = 0; c < 32; ++c) {
      EXPECT_NEAR(points[c].t_s - t0, 111e-6 * b + 55.5e-6 * (c / 16) + 2.8e-6 * (c % 16), kDecodeTimeTolerance_s);
      EXPECT_EQ(points[c].laser, c % 16);
      EXPECT_EQ(points[c].intensity, c);
      EXPECT_EQ(points[c].return_index, 0);
    }
  }
}

TEST(Rs16MsopDecode, AzimuthInterpolatesAcrossTheBlockAndWraps) {
  // 359.00, 359.40, ... wraps through 0 at block 3.
  const Decoded d = decode(encode_msop(packet_with_azimuths(359.0, 0.4)), flat_lasers());
  for (int b = 0; b < 12; ++b) {
    const auto points = d.packet.block_points(b);
    const double start = std::fmod(359.0 + 0.4 * b, 360.0);
    for (int c = 0; c < 32; ++c) {
      const double expected = std::fmod(start + 0.4 * (55.5 * (c / 16) + 2.8 * (c % 16)) / 111.0, 360.0);
      EXPECT_NEAR(points[c].azimuth_deg, expected, 2e-4) << "block " << b << " channel " << c;
      const double a = expected * kDegToRad;
      EXPECT_NEAR(points[c].x_m, (10.0 + kOpticalCentreOffset_m) * std::cos(a), 1e-5);
      EXPECT_NEAR(points[c].y_m, -(10.0 + kOpticalCentreOffset_m) * std::sin(a), 1e-5);
    }
  }
}

TEST(Rs16MsopDecode, LastBlockTurnsLikeTheOneBefore) {
  MsopPacketData p = packet_with_azimuths(100.0, 0.4);
  p.blocks[11].azimuth_deg = p.blocks[10].azimuth_deg + 0.3;  // slower between the last two
  const Decoded d = decode(encode_msop(p), flat_lasers());
  const auto last = d.packet.block_points(11);
  EXPECT_NEAR(last[31].azimuth_deg, p.blocks[11].azimuth_deg + 0.3 * (55.5 + 42.0) / 111.0, 2e-4);
}

TEST(Rs16MsopDecode, FovGapUsesTheNominalStep) {
  MsopPacketData p = packet_with_azimuths(100.0, 0.4);
  for (int b = 6; b < 12; ++b) p.blocks[b].azimuth_deg += 50.0;  // blind sector between blocks 5 and 6
  PointSettings settings;
  settings.rpm = 600.0;
  const Decoded d = decode(encode_msop(p), flat_lasers(), settings);
  const double nominal_deg = 600.0 * 6.0 * 111e-6;
  const auto before_gap = d.packet.block_points(5);
  EXPECT_NEAR(before_gap[31].azimuth_deg, p.blocks[5].azimuth_deg + nominal_deg * (55.5 + 42.0) / 111.0, 2e-4);
  const auto after_gap = d.packet.block_points(6);
  EXPECT_NEAR(after_gap[31].azimuth_deg, p.blocks[6].azimuth_deg + 0.4 * (55.5 + 42.0) / 111.0, 2e-4);
}

TEST(Rs16MsopDecode, RangesOutsideLimitsAreDroppedByReason) {
  MsopPacketData p = packet_with_azimuths(0.0, 0.4);
  p.blocks[0].channels[0].distance_m = 0.0;
  p.blocks[0].channels[1].distance_m = 0.3;
  p.blocks[0].channels[2].distance_m = 0.4;   // the limit itself is kept
  p.blocks[0].channels[3].distance_m = 200.0;
  p.blocks[0].channels[4].distance_m = 200.5;
  p.blocks[3].channels[7].distance_m = 0.0;
  const Decoded d = decode(encode_msop(p), flat_lasers());
  EXPECT_EQ(d.dropped.zero_range, 2u);
  EXPECT_EQ(d.dropped.too_near, 1u);
  EXPECT_EQ(d.dropped.too_far, 1u);
  EXPECT_EQ(d.packet.all_points().size(), 384u - 4u);
  EXPECT_EQ(d.packet.block_dropped[0], 3);
  EXPECT_EQ(d.packet.block_dropped[3], 1);
  EXPECT_EQ(d.packet.block_points(0).size(), 29u);

  PointSettings wide;
  wide.min_range_m = 0.1;
  wide.max_range_m = 250.0;
  const Decoded w = decode(encode_msop(p), flat_lasers(), wide);
  EXPECT_EQ(w.dropped.total(), 2u);
}

TEST(Rs16MsopDecode, ResolutionScalesTheRawDistance) {
  const auto bytes = encode_msop(packet_with_azimuths(0.0, 0.0), 0.005);  // raw 2000
  PointSettings coarse;
  coarse.resolution_m = 0.01;
  const Decoded d = decode(bytes, flat_lasers(), coarse);
  EXPECT_NEAR(d.packet.points[0].x_m, 20.0 + kOpticalCentreOffset_m, 1e-5);
}

TEST(Rs16MsopDecode, TemperatureAsTheManualGivesIt) {
  auto bytes = encode_msop(packet_with_azimuths(0.0, 0.4));
  bytes[38] = 0x88;
  bytes[39] = 0x11;
  MsopHeader h;
  ASSERT_EQ(parse_msop_header(bytes, h), PacketError::None);
  EXPECT_DOUBLE_EQ(h.temperature_c, 35.0625);
  bytes[39] = 0x91;  // sign bit
  ASSERT_EQ(parse_msop_header(bytes, h), PacketError::None);
  EXPECT_DOUBLE_EQ(h.temperature_c, -35.0625);
}

TEST(Rs16MsopDecode, DualReturnPairsBothReturnsOfEachFiring) {
  const Decoded d = [] {
    PointSettings dual;
    dual.return_mode = ReturnMode::Dual;
    MsopPacketData p = packet_with_azimuths(0.0, 0.2);
    for (int c = 16; c < 32; ++c) p.blocks[0].channels[c].distance_m = 20.0;
    return decode(encode_msop(p), flat_lasers(), dual);
  }();
  const double t0 = kT0Ns * 1e-9;
  const auto block = d.packet.block_points(1);
  ASSERT_EQ(block.size(), 32u);
  for (int i = 0; i < 32; ++i) {
    EXPECT_EQ(block[i].laser, i / 2);
    EXPECT_EQ(block[i].return_index, i % 2);
    EXPECT_NEAR(block[i].t_s - t0, 55.5e-6 * 1 + 2.8e-6 * (i / 2), kDecodeTimeTolerance_s);
    EXPECT_NEAR(block[i].azimuth_deg, 0.2 + 0.2 * 2.8 * (i / 2) / 55.5, 2e-4);
  }
  const auto first = d.packet.block_points(0);
  EXPECT_NEAR(first[1].x_m, 20.0 + kOpticalCentreOffset_m, 1e-4);  // second return of laser 0
  EXPECT_NEAR(first[0].x_m, 10.0 + kOpticalCentreOffset_m, 1e-4);
}

TEST(Rs16MsopDecode, MalformedPacketsAreRejectedWithTheirReason) {
  const auto good = encode_msop(packet_with_azimuths(0.0, 0.4));
  MsopHeader h;
  EXPECT_EQ(parse_msop_header(std::span(good).first(1247), h), PacketError::WrongSize);
  EXPECT_EQ(parse_msop_header({}, h), PacketError::WrongSize);
  std::vector<std::uint8_t> longer(good.begin(), good.end());
  longer.push_back(0);
  EXPECT_EQ(parse_msop_header(longer, h), PacketError::WrongSize);
  auto bad = good;
  bad[3] ^= 0xFF;
  EXPECT_EQ(parse_msop_header(bad, h), PacketError::WrongMagic);
  bad = good;
  bad[1247] = 0xFE;
  EXPECT_EQ(parse_msop_header(bad, h), PacketError::WrongTail);
  bad = good;
  bad[kMsopTimeOffset + 1] = 13;  // month
  EXPECT_EQ(parse_msop_header(bad, h), PacketError::BadTimestamp);
  bad = good;
  bad[kFirstBlockOffset + 1] = 0xDD;
  EXPECT_EQ(parse_msop_header(bad, h), PacketError::NoValidBlocks);
}

TEST(Rs16MsopDecode, AWrongFlagOrAzimuthEndsTheValidBlocks) {
  auto bytes = encode_msop(packet_with_azimuths(0.0, 0.4));
  bytes[kFirstBlockOffset + kBlockSize * 7] = 0x00;
  MsopHeader h;
  ASSERT_EQ(parse_msop_header(bytes, h), PacketError::None);
  EXPECT_EQ(h.valid_blocks, 7);
  write_u16_be(bytes, kFirstBlockOffset + kBlockSize * 4 + kBlockAzimuthOffset, 36000);
  ASSERT_EQ(parse_msop_header(bytes, h), PacketError::None);
  EXPECT_EQ(h.valid_blocks, 4);
  DecodedPacket packet;
  DroppedPoints dropped;
  decode_msop_points(bytes, h, 0.0, flat_lasers(), {}, packet, dropped);
  EXPECT_EQ(packet.block_count, 4);
  EXPECT_EQ(packet.all_points().size(), 4u * 32u);
}

}  // namespace
}  // namespace tumble::rs16
