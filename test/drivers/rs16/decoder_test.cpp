#include "drivers/rs16/decoder.hpp"

#include <gtest/gtest.h>

#include "drivers/rs16/difop_encode.hpp"
#include "test/drivers/rs16/packet_stream.hpp"

namespace tumble::rs16 {
namespace {

DifopData difop_with_angles(double offset_deg) {
  DifopData d;
  for (int i = 0; i < 16; ++i) d.vertical_angles_deg[i] = kDesignVerticalAnglesDeg[i] + (i < 8 ? offset_deg : -offset_deg);
  return d;
}

TEST(Rs16Decoder, AnglesComeFromDesignThenConfigThenDifop) {
  DecoderStats stats;
  Decoder design;
  EXPECT_EQ(design.lasers().source, AngleSource::Design);
  EXPECT_EQ(design.lasers().vertical_deg, kDesignVerticalAnglesDeg);

  DecoderConfig config;
  std::array<double, 16> mine = kDesignVerticalAnglesDeg;
  mine[3] = -9.5;
  config.vertical_angles_deg = mine;
  Decoder decoder(config);
  EXPECT_EQ(decoder.lasers().source, AngleSource::Config);
  EXPECT_DOUBLE_EQ(decoder.lasers().vertical_deg[3], -9.5);

  decoder.decode_difop(encode_difop(DifopData{}), stats);  // uncalibrated: keep ours
  EXPECT_EQ(decoder.lasers().source, AngleSource::Config);
  EXPECT_EQ(stats.difop_uncalibrated, 1u);

  decoder.decode_difop(encode_difop(difop_with_angles(0.0123)), stats);
  EXPECT_EQ(decoder.lasers().source, AngleSource::Difop);
  EXPECT_NEAR(decoder.lasers().vertical_deg[0], -14.9877, 1e-9);
  EXPECT_EQ(stats.difop_packets, 2u);
}

TEST(Rs16Decoder, DifopSetsResolutionReturnModeAndSpeed) {
  Decoder decoder;
  DecoderStats stats;
  DifopData d = difop_with_angles(0.0);
  d.top_firmware = {0x00, 0x00, 0x00};
  d.return_mode = 0;
  d.motor_rpm = 1200;
  decoder.decode_difop(encode_difop(d), stats);
  EXPECT_DOUBLE_EQ(decoder.resolution_m(), 0.01);
  EXPECT_EQ(decoder.return_mode(), ReturnMode::Dual);
  EXPECT_DOUBLE_EQ(decoder.rpm(), 1200.0);

  d.return_mode = 7;  // not a mode: keep the last one
  d.motor_rpm = 0;    // not a speed: keep the last one
  decoder.decode_difop(encode_difop(d), stats);
  EXPECT_EQ(decoder.return_mode(), ReturnMode::Dual);
  EXPECT_DOUBLE_EQ(decoder.rpm(), 1200.0);

  // Points now come out at 1 cm per raw unit.
  test::StreamSpec spec;
  spec.mode = ReturnMode::Dual;
  const auto bytes = encode_msop(test::stream_packet(spec, 0), 0.005);  // raw 2000
  DecodedPacket packet;
  ASSERT_TRUE(decoder.decode_msop(bytes, 0.0, packet, stats));
  EXPECT_NEAR(packet.points[0].x_m * packet.points[0].x_m + packet.points[0].y_m * packet.points[0].y_m +
                  packet.points[0].z_m * packet.points[0].z_m,
              400.0, 2.0);
  EXPECT_EQ(packet.return_mode, ReturnMode::Dual);
}

// The first DIFOP with vertical angles sets the sensor configuration; one
// that disagrees later (another host, a glitch) changes nothing.
TEST(Rs16Decoder, ALaterDifopThatDisagreesIsCountedAndIgnoredUnlessFollowed) {
  DifopData first = difop_with_angles(0.01);
  first.motor_rpm = 600;
  DifopData other = difop_with_angles(0.5);
  other.motor_rpm = 1200;
  other.return_mode = 0;
  for (const bool follow : {false, true}) {
    DecoderConfig config;
    config.follow_difop_changes = follow;
    Decoder decoder(config);
    DecoderStats stats;
    decoder.decode_difop(encode_difop(first), stats);
    decoder.decode_difop(encode_difop(first), stats);  // agrees: nothing to count
    for (int i = 0; i < 3; ++i) decoder.decode_difop(encode_difop(other), stats);
    EXPECT_EQ(stats.difop_packets, 5u);
    EXPECT_EQ(stats.difop_ignored, follow ? 0u : 3u);
    EXPECT_NEAR(decoder.lasers().vertical_deg[0], -15.0 + (follow ? 0.5 : 0.01), 1e-9);
    EXPECT_DOUBLE_EQ(decoder.rpm(), follow ? 1200.0 : 600.0);
    EXPECT_EQ(decoder.return_mode(), follow ? ReturnMode::Dual : ReturnMode::Strongest);
  }
}

TEST(Rs16Decoder, WaitsForDifopWhenAsked) {
  DecoderConfig config;
  config.wait_for_difop = true;
  Decoder decoder(config);
  DecoderStats stats;
  DecodedPacket packet;
  const auto msop = encode_msop(test::stream_packet({}, 0));
  EXPECT_FALSE(decoder.decode_msop(msop, 0.0, packet, stats));
  EXPECT_EQ(stats.msop_before_difop, 1u);
  decoder.decode_difop(encode_difop(difop_with_angles(0.0)), stats);
  EXPECT_TRUE(decoder.decode_msop(msop, 0.0, packet, stats));
  EXPECT_EQ(stats.msop_packets, 1u);
  EXPECT_EQ(stats.points, 384u);
}

TEST(Rs16Decoder, BadPacketsAreCountedNotThrown) {
  Decoder decoder;
  DecoderStats stats;
  DecodedPacket packet;
  auto msop = encode_msop(test::stream_packet({}, 0));
  msop[0] = 0;
  EXPECT_FALSE(decoder.decode_msop(msop, 0.0, packet, stats));
  EXPECT_FALSE(decoder.decode_msop(std::span(msop).first(100), 0.0, packet, stats));
  auto difop = encode_difop(difop_with_angles(0.0));
  difop[1247] = 0;
  decoder.decode_difop(difop, stats);
  decoder.decode_difop({}, stats);
  EXPECT_EQ(stats.bad_msop.wrong_magic, 1u);
  EXPECT_EQ(stats.bad_msop.wrong_size, 1u);
  EXPECT_EQ(stats.bad_difop.wrong_tail, 1u);
  EXPECT_EQ(stats.bad_difop.wrong_size, 1u);
  EXPECT_EQ(stats.msop_packets + stats.difop_packets, 0u);
}

TEST(Rs16Decoder, SyncedClockUsesHeaderTimeFreeClockMapsToArrival) {
  const test::StreamSpec spec;
  const double header_s = spec.start_ns * 1e-9;
  const double host_offset_s = -3600.0 * 24 * 365;  // the lidar clock is a year ahead of the host
  const double latency_s = 150e-6;
  DecodedPacket packet;
  DecoderStats stats;

  Decoder synced;
  ASSERT_TRUE(synced.decode_msop(encode_msop(test::stream_packet(spec, 0)), header_s + 5.0, packet, stats));
  EXPECT_DOUBLE_EQ(packet.t_s, header_s);

  DecoderConfig config;
  config.clock = ClockMode::Free;
  Decoder free(config);
  for (int i = 0; i < 2000; ++i) {
    const double first_firing_host_s = header_s + host_offset_s + i * 1332e-6;
    const double arrival_s = first_firing_host_s + 1332e-6 + latency_s + (i % 7 == 0 ? 0.0 : 40e-6 * (i % 5));
    ASSERT_TRUE(free.decode_msop(encode_msop(test::stream_packet(spec, i)), arrival_s, packet, stats));
    EXPECT_NEAR(packet.t_s, first_firing_host_s + latency_s, 1e-5) << "packet " << i;
    EXPECT_NEAR(packet.lidar_t_s, header_s + i * 1332e-6, 1e-6);
  }
}

TEST(Rs16Decoder, RefusesConfigOutOfRange) {
  DecoderConfig c;
  c.min_range_m = -1.0;
  EXPECT_THROW(Decoder{c}, std::invalid_argument);
  c = {};
  c.max_range_m = 0.2;
  EXPECT_THROW(Decoder{c}, std::invalid_argument);
  c = {};
  c.default_rpm = 0.0;
  EXPECT_THROW(Decoder{c}, std::invalid_argument);
  c = {};
  std::array<double, 16> angles{};
  angles[4] = 91.0;
  c.vertical_angles_deg = angles;
  try {
    Decoder d(c);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("vertical_angles_deg[4]"), std::string::npos);
  }
}

}  // namespace
}  // namespace tumble::rs16
