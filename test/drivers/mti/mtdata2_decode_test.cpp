#include "drivers/mti/mtdata2_decode.hpp"

#include <gtest/gtest.h>

#include "drivers/mti/mtdata2_encode.hpp"
#include "drivers/mti/mtdata2_packets.hpp"
#include "drivers/mti/xdi.hpp"

namespace tumble::mti {
namespace {

using Bytes = std::vector<std::uint8_t>;

TEST(MtData2Decode, EveryKnownRealOutputInEveryFormat) {
  const std::array<double, 9> v{0.5, -1.25, 2.0, -0.125, 0.75, 3.5, -2.5, 1.0, 0.25};  // exact in all formats
  for (const NumberFormat f :
       {NumberFormat::Float32, NumberFormat::Fp1220, NumberFormat::Fp1632, NumberFormat::Float64}) {
    Bytes p;
    append_reals_packet(p, xdi::kTemperature, std::span(v).first(1), f);
    append_reals_packet(p, xdi::kQuaternion, std::span(v).first(4), f);
    append_reals_packet(p, xdi::kRotationMatrix | 0x4, v, f);
    append_reals_packet(p, xdi::kEulerAngles | 0x8, std::span(v).first(3), f);
    append_reals_packet(p, xdi::kDeltaV, std::span(v).first(3), f);
    append_reals_packet(p, xdi::kAcceleration, std::span(v).first(3), f);
    append_reals_packet(p, xdi::kFreeAcceleration, std::span(v).first(3), f);
    append_reals_packet(p, xdi::kAltitudeEllipsoid, std::span(v).first(1), f);
    append_reals_packet(p, xdi::kPositionEcef, std::span(v).first(3), f);
    append_reals_packet(p, xdi::kLatLon, std::span(v).first(2), f);
    append_reals_packet(p, xdi::kRateOfTurn, std::span(v).first(3), f);
    append_reals_packet(p, xdi::kDeltaQ, std::span(v).first(4), f);
    append_reals_packet(p, xdi::kMagneticField, std::span(v).first(3), f);
    append_reals_packet(p, xdi::kVelocityXyz, std::span(v).first(3), f);
    MtData2 m;
    MtData2DecodeStats stats;
    ASSERT_TRUE(decode_mtdata2(p, m, stats)) << number_format_name(f);
    const Eigen::Vector3d v3(v[0], v[1], v[2]);
    const std::array<double, 4> v4{v[0], v[1], v[2], v[3]};
    EXPECT_EQ(m.temperature_c, v[0]);
    EXPECT_EQ(m.quaternion, v4);
    EXPECT_EQ(m.rotation_matrix, v);
    EXPECT_EQ(*m.euler_angles_deg, v3);
    EXPECT_EQ(m.orientation_xdi, static_cast<std::uint16_t>(xdi::kEulerAngles | 0x8 | static_cast<int>(f)));
    EXPECT_EQ(*m.delta_v_m_s, v3);
    EXPECT_EQ(*m.acceleration_m_s2, v3);
    EXPECT_EQ(*m.free_acceleration_m_s2, v3);
    EXPECT_EQ(m.altitude_ellipsoid_m, v[0]);
    EXPECT_EQ(*m.position_ecef_m, v3);
    EXPECT_EQ(m.lat_lon_deg, (std::array<double, 2>{v[0], v[1]}));
    EXPECT_EQ(*m.rate_of_turn_rad_s, v3);
    EXPECT_EQ(m.delta_q, v4);
    EXPECT_EQ(*m.magnetic_field_au, v3);
    EXPECT_EQ(*m.velocity_m_s, v3);
    EXPECT_EQ(stats.messages, 1u);
    EXPECT_EQ(stats.size_mismatches + stats.unknown_packets + stats.truncated_messages, 0u);
  }
}

TEST(MtData2Decode, IntegerOutputsIgnoreTheirFormatBits) {
  Bytes p;
  append_u16_packet(p, xdi::kPacketCounter, 65535);
  append_u32_packet(p, xdi::kSampleTimeFine, 863'999'999);
  append_u32_packet(p, xdi::kSampleTimeCoarse, 86399);
  append_u32_packet(p, xdi::kBaroPressure | 0x3, 101669);  // an MTi-300 sends this (fixture)
  append_u32_packet(p, xdi::kStatusWord, 0x00481401);
  append_raw_packet(p, xdi::kStatusByte, Bytes{0x45});
  MtData2 m;
  MtData2DecodeStats stats;
  ASSERT_TRUE(decode_mtdata2(p, m, stats));
  EXPECT_EQ(m.packet_counter, 65535);
  EXPECT_EQ(m.sample_time_fine, 863'999'999u);
  EXPECT_EQ(m.sample_time_coarse, 86399u);
  EXPECT_EQ(m.baro_pressure_pa, 101669u);
  EXPECT_EQ(m.status_word, 0x00481401u);
  EXPECT_EQ(m.status_byte, 0x45);
}

TEST(MtData2Decode, UnknownOutputsAreSkippedBySize) {
  Bytes p;
  append_raw_packet(p, 0xA010, Bytes(20, 0xFA));  // raw sensor data: not decoded here
  append_u16_packet(p, xdi::kPacketCounter, 7);
  append_raw_packet(p, 0x1030, Bytes(4, 1));  // ITOW
  MtData2 m;
  MtData2DecodeStats stats;
  ASSERT_TRUE(decode_mtdata2(p, m, stats));
  EXPECT_EQ(m.packet_counter, 7);
  EXPECT_EQ(stats.unknown_packets, 2u);
}

TEST(MtData2Decode, APacketOfTheWrongSizeIsSkippedAndCounted) {
  Bytes p;
  append_raw_packet(p, xdi::kAcceleration, Bytes(8, 0));  // Float32 needs 12
  append_raw_packet(p, xdi::kRateOfTurn | 0x2, Bytes(12, 0));  // Fp16.32 needs 18
  append_raw_packet(p, xdi::kGnssSatInfo, Bytes(10, 0));  // 8 + 4 per satellite
  append_u32_packet(p, xdi::kSampleTimeFine, 1234);
  MtData2 m;
  MtData2DecodeStats stats;
  ASSERT_TRUE(decode_mtdata2(p, m, stats));
  EXPECT_FALSE(m.acceleration_m_s2);
  EXPECT_FALSE(m.rate_of_turn_rad_s);
  EXPECT_FALSE(m.gnss_sat_info);
  EXPECT_EQ(m.sample_time_fine, 1234u);
  EXPECT_EQ(stats.size_mismatches, 3u);
}

TEST(MtData2Decode, ACutChainDropsTheWholeMessage) {
  Bytes p = encode_mtdata2(MtData2Out{});
  for (const std::size_t keep : {p.size() - 1, std::size_t{4}, std::size_t{1}}) {
    const Bytes cut(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(keep));
    MtData2 m;
    MtData2DecodeStats stats;
    EXPECT_FALSE(decode_mtdata2(cut, m, stats)) << keep;
    EXPECT_FALSE(m.packet_counter);
    EXPECT_EQ(stats.truncated_messages, 1u);
    EXPECT_EQ(stats.messages, 0u);
  }
}

TEST(MtData2Decode, EmptyPayloadIsAnEmptyMessage) {
  MtData2 m;
  MtData2DecodeStats stats;
  EXPECT_TRUE(decode_mtdata2({}, m, stats));
  EXPECT_FALSE(m.packet_counter);
  EXPECT_EQ(stats.messages, 1u);
}

TEST(MtData2PacketReader, WalksTheChainInOrder) {
  Bytes p;
  append_u16_packet(p, xdi::kPacketCounter, 1);
  append_raw_packet(p, 0x1234, {});
  append_u32_packet(p, xdi::kStatusWord, 2);
  MtData2PacketReader reader(p);
  std::vector<std::uint16_t> xdis;
  while (const auto packet = reader.next()) xdis.push_back(packet->xdi);
  EXPECT_EQ(xdis, (std::vector<std::uint16_t>{xdi::kPacketCounter, 0x1234, xdi::kStatusWord}));
  EXPECT_FALSE(reader.truncated());
}

TEST(Xdi, ExpectedSizesFollowTheNumberFormat) {
  EXPECT_EQ(xdi::expected_size(0x4020), 12u);
  EXPECT_EQ(xdi::expected_size(0x4021), 12u);
  EXPECT_EQ(xdi::expected_size(0x4022), 18u);
  EXPECT_EQ(xdi::expected_size(0x4023), 24u);
  EXPECT_EQ(xdi::expected_size(0x8033), 32u);
  EXPECT_EQ(xdi::expected_size(0x2023), 72u);
  EXPECT_EQ(xdi::expected_size(0x7010), 94u);
  EXPECT_EQ(xdi::expected_size(0x1010), 12u);
  EXPECT_EQ(xdi::expected_size(0xE010), 1u);
  EXPECT_FALSE(xdi::expected_size(0x7020));
  EXPECT_TRUE(xdi::size_fits(0x7020, 8 + 4 * 28));
  EXPECT_FALSE(xdi::expected_size(0xA010));
}

}  // namespace
}  // namespace tumble::mti
