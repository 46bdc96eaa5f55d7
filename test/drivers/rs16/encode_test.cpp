// The encoders the simulator relies on: decode(encode(x)) == x for what the
// packets can represent, and re-encoding decoded capture packets gives back
// their bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drivers/rs16/difop_decode.hpp"
#include "drivers/rs16/difop_encode.hpp"
#include "drivers/rs16/msop_decode.hpp"
#include "drivers/rs16/msop_encode.hpp"
#include "drivers/rs16/packet_layout.hpp"
#include "drivers/rs16/pcap_source.hpp"
#include "test/fixtures.hpp"

namespace tumble::rs16 {
namespace {

MsopPacketData varied_packet() {
  MsopPacketData p;
  p.utc_time_ns = 1'717'171'717'123'456'000;
  p.temperature_c = -12.5;
  for (int b = 0; b < 12; ++b) {
    p.blocks[b].azimuth_deg = 359.61 + 0.4 * b - (b >= 1 ? 360.0 : 0.0);
    for (int c = 0; c < 32; ++c)
      p.blocks[b].channels[c] = {(c * 37 + b * 11) % 50 == 0 ? 0.0 : 0.005 * (100 + 997 * c + 31 * b),
                                 static_cast<std::uint8_t>(b * 20 + c)};
  }
  return p;
}

TEST(Rs16Encode, MsopRoundTripsEveryField) {
  for (const double resolution : {0.005, 0.01}) {
    const MsopPacketData p = varied_packet();
    const auto bytes = encode_msop(p, resolution);
    MsopPacketData back;
    MsopHeader header;
    ASSERT_EQ(decode_msop_fields(bytes, resolution, back, header), PacketError::None);
    EXPECT_EQ(header.valid_blocks, 12);
    EXPECT_EQ(back.utc_time_ns, p.utc_time_ns);
    EXPECT_DOUBLE_EQ(back.temperature_c, p.temperature_c);
    for (int b = 0; b < 12; ++b) {
      const double wrapped = std::fmod(p.blocks[b].azimuth_deg + 360.0, 360.0);
      EXPECT_NEAR(back.blocks[b].azimuth_deg, wrapped, 1e-9) << "block " << b;
      for (int c = 0; c < 32; ++c) {
        EXPECT_NEAR(back.blocks[b].channels[c].distance_m, p.blocks[b].channels[c].distance_m, resolution / 2 + 1e-12);
        EXPECT_EQ(back.blocks[b].channels[c].reflectivity, p.blocks[b].channels[c].reflectivity);
      }
    }
    EXPECT_EQ(encode_msop(back, resolution), bytes);
  }
}

TEST(Rs16Encode, MsopSendsUnrepresentableRangesAsNoReturn) {
  MsopPacketData p = varied_packet();
  p.blocks[0].channels[0].distance_m = 65536 * 0.005;
  p.blocks[0].channels[1].distance_m = -1.0;
  const auto bytes = encode_msop(p);
  EXPECT_EQ(read_u16_be(bytes, kFirstBlockOffset + kBlockChannelsOffset), 0);
  EXPECT_EQ(read_u16_be(bytes, kFirstBlockOffset + kBlockChannelsOffset + 3), 0);
}

TEST(Rs16Encode, MsopRefusesWhatItCannotEncode) {
  MsopPacketData p = varied_packet();
  EXPECT_THROW(encode_msop(p, 0.0), std::invalid_argument);
  p.blocks[3].azimuth_deg = std::nan("");
  EXPECT_THROW(encode_msop(p), std::invalid_argument);
  p = varied_packet();
  p.utc_time_ns = 0;
  EXPECT_THROW(encode_msop(p), std::out_of_range);
}

DifopData varied_difop() {
  DifopData d;
  d.motor_rpm = 1200;
  for (int i = 0; i < 16; ++i) d.vertical_angles_deg[i] = (i < 8 ? -1.0 : 1.0) * (15.0 - 2.0 * (i % 8) + 0.0123);
  d.return_mode = 0;
  d.top_firmware = {0x55, 0xAA, 0x5A};
  d.utc_time_ns = 1'704'067'200'250'000'000;
  d.serial = {1, 2, 3, 4, 5, 6};
  return d;
}

TEST(Rs16Encode, DifopRoundTripsEveryField) {
  const DifopData d = varied_difop();
  DifopInfo back;
  ASSERT_EQ(decode_difop(encode_difop(d), back), PacketError::None);
  EXPECT_EQ(back.data.motor_rpm, d.motor_rpm);
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(back.data.vertical_angles_deg[i], d.vertical_angles_deg[i], 0.5e-4);
  EXPECT_EQ(back.data.return_mode, d.return_mode);
  EXPECT_EQ(back.data.top_firmware, d.top_firmware);
  EXPECT_EQ(back.data.utc_time_ns, d.utc_time_ns);
  EXPECT_EQ(back.data.serial, d.serial);
  EXPECT_TRUE(back.angles_calibrated);
  EXPECT_TRUE(back.time_valid);
  EXPECT_DOUBLE_EQ(back.resolution_m, 0.01);
  EXPECT_EQ(encode_difop(back.data), encode_difop(d));
}

TEST(Rs16Encode, DifopDefaultsSayUncalibratedAndClockUnset) {
  DifopInfo back;
  ASSERT_EQ(decode_difop(encode_difop(DifopData{}), back), PacketError::None);
  EXPECT_FALSE(back.angles_calibrated);
  EXPECT_FALSE(back.time_valid);
  EXPECT_DOUBLE_EQ(back.resolution_m, 0.005);
}

TEST(Rs16Encode, DifopRefusesAnglesOnTheWrongSide) {
  DifopData d = varied_difop();
  d.vertical_angles_deg[2] = 3.0;  // lasers 0..7 point down
  try {
    encode_difop(d);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("laser 2"), std::string::npos);
  }
  d = varied_difop();
  d.vertical_angles_deg[9] = 2000.0;
  EXPECT_THROW(encode_difop(d), std::invalid_argument);
}

TEST(Rs16Encode, ReencodingCapturePacketsGivesTheirBytes) {
  TUMBLE_REQUIRE_FIXTURE("rs16/rs16_synthetic.pcap");
  PcapSource source(tumble::test::fixture_path("rs16/rs16_synthetic.pcap").string(), {});
  double resolution_m = 0.005;
  int msop = 0, difop = 0;
  while (const auto d = source.next()) {
    if (d->kind == PacketKind::Difop) {
      DifopInfo info;
      ASSERT_EQ(decode_difop(d->payload, info), PacketError::None);
      resolution_m = info.resolution_m;
      const auto again = encode_difop(info.data);
      // Addresses, ports, FOV and the other firmware bytes are not in DifopData.
      const std::vector<std::pair<std::size_t, std::size_t>> representable{
          {0, 10}, {41, 44}, {292, 298}, {300, 301}, {303, 313}, {1165, 1213}, {1246, 1248}};
      for (const auto& [from, to] : representable)
        for (std::size_t i = from; i < to; ++i) EXPECT_EQ(again[i], d->payload[i]) << "DIFOP byte " << i;
      ++difop;
    } else {
      MsopPacketData fields;
      MsopHeader header;
      ASSERT_EQ(decode_msop_fields(d->payload, resolution_m, fields, header), PacketError::None);
      const auto again = encode_msop(fields, resolution_m);
      ASSERT_TRUE(std::equal(again.begin(), again.end(), d->payload.begin(), d->payload.end()))
          << "MSOP packet " << msop;
      ++msop;
    }
  }
  EXPECT_GT(msop, 0);
  EXPECT_GT(difop, 0);
}

}  // namespace
}  // namespace tumble::rs16
