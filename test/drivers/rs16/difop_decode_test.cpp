#include "drivers/rs16/difop_decode.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "drivers/rs16/packet_layout.hpp"

namespace tumble::rs16 {
namespace {

DifopData calibrated() {
  DifopData d;
  for (int i = 0; i < 16; ++i) d.vertical_angles_deg[i] = (i < 8 ? -1.0 : 1.0) * (1.0 + 2.0 * (7 - i % 8)) + 0.0007;
  d.vertical_angles_deg[0] = -14.9994;
  return d;
}

TEST(Rs16DifopDecode, ResolutionFollowsTopBoardFirmware) {
  using Bytes = std::array<std::uint8_t, 3>;
  for (const Bytes old : {Bytes{0x00, 0x00, 0x00}, Bytes{0xFF, 0xFF, 0xFF}, Bytes{0x55, 0xAA, 0x5A}})
    EXPECT_DOUBLE_EQ(range_resolution_m(old), 0.01);
  for (const Bytes current : {Bytes{0x23, 0x0A, 0x01}, Bytes{0x00, 0x00, 0x01}, Bytes{0x55, 0xAA, 0x5B}})
    EXPECT_DOUBLE_EQ(range_resolution_m(current), 0.005);
}

TEST(Rs16DifopDecode, ReadsTheFirmwareBytesAt41To43) {
  auto bytes = encode_difop(calibrated());
  bytes[40] = 0x06;  // first and last byte of the 5-byte field do not count
  bytes[44] = 0x41;
  std::fill_n(bytes.begin() + 41, 3, 0xFF);
  DifopInfo info;
  ASSERT_EQ(decode_difop(bytes, info), PacketError::None);
  EXPECT_DOUBLE_EQ(info.resolution_m, 0.01);
}

TEST(Rs16DifopDecode, KeepsAnglesAtTenThousandthsOfADegree) {
  DifopInfo info;
  ASSERT_EQ(decode_difop(encode_difop(calibrated()), info), PacketError::None);
  ASSERT_TRUE(info.angles_calibrated);
  EXPECT_DOUBLE_EQ(info.data.vertical_angles_deg[0], -14.9994);
  EXPECT_DOUBLE_EQ(info.data.vertical_angles_deg[15], 1.0007);
  EXPECT_DOUBLE_EQ(info.data.vertical_angles_deg[7], -0.9993);
}

TEST(Rs16DifopDecode, BlankOrImplausibleAnglesAreNotCalibrated) {
  auto bytes = encode_difop(calibrated());
  DifopInfo info;
  std::fill_n(bytes.begin() + kDifopVerticalAnglesOffset, 48, 0xFF);
  ASSERT_EQ(decode_difop(bytes, info), PacketError::None);
  EXPECT_FALSE(info.angles_calibrated);
  std::fill_n(bytes.begin() + kDifopVerticalAnglesOffset, 48, 0x00);
  ASSERT_EQ(decode_difop(bytes, info), PacketError::None);
  EXPECT_FALSE(info.angles_calibrated);
  bytes = encode_difop(calibrated());
  write_u24_be(bytes, kDifopVerticalAnglesOffset + 3 * 5, 400000);  // 40 deg
  ASSERT_EQ(decode_difop(bytes, info), PacketError::None);
  EXPECT_FALSE(info.angles_calibrated);
}

TEST(Rs16DifopDecode, MalformedPacketsAreRejectedWithTheirReason) {
  const auto good = encode_difop(calibrated());
  DifopInfo info;
  EXPECT_EQ(decode_difop(std::span(good).first(1000), info), PacketError::WrongSize);
  auto bad = good;
  bad[0] = 0x55;
  EXPECT_EQ(decode_difop(bad, info), PacketError::WrongMagic);
  bad = good;
  bad[1246] = 0x00;
  EXPECT_EQ(decode_difop(bad, info), PacketError::WrongTail);
}

}  // namespace
}  // namespace tumble::rs16
