#include "drivers/mti/commands.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "drivers/mti/baud.hpp"
#include "drivers/mti/configurator.hpp"
#include "drivers/mti/device_error.hpp"
#include "drivers/mti/product_code.hpp"
#include "drivers/mti/xdi.hpp"

namespace tumble::mti {
namespace {

using Bytes = std::vector<std::uint8_t>;
constexpr double kDeg = std::numbers::pi / 180;

TEST(Commands, SetBaudrateCarriesTheMtiCode) {
  EXPECT_EQ(encode_set_baudrate(460800), (Bytes{0xFA, 0xFF, 0x18, 0x01, 0x00, 0xE8}));
  EXPECT_EQ(encode_set_baudrate(921600), (Bytes{0xFA, 0xFF, 0x18, 0x01, 0x80, 0x68}));
  EXPECT_EQ(encode_set_baudrate(115200), (Bytes{0xFA, 0xFF, 0x18, 0x01, 0x02, 0xE6}));
  EXPECT_THROW(encode_set_baudrate(100000), std::invalid_argument);
  EXPECT_EQ(encode_reset(), (Bytes{0xFA, 0xFF, 0x40, 0x00, 0xC1}));
}

TEST(Commands, BaudCodesRoundTrip) {
  for (const std::uint32_t baud : {4800u, 9600u, 19200u, 38400u, 57600u, 115200u, 230400u, 460800u, 921600u}) {
    const auto code = baud_code(baud);
    ASSERT_TRUE(code) << baud;
    EXPECT_EQ(baud_from_code(*code), baud);
  }
  EXPECT_EQ(baud_from_code(0x0A), 921600u);  // legacy second code
  EXPECT_FALSE(baud_code(250000));
  EXPECT_FALSE(baud_from_code(0x77));
}

// 54 bytes * 10 bits * 400 Hz = 216 kbit/s: with the line at most half busy
// that needs 460800 baud; 100 Hz fits the default 115200.
TEST(Commands, BaudMustCarryTheRate) {
  EXPECT_EQ(configured_frame_bytes(NumberFormat::Float32), 54u);
  EXPECT_EQ(configured_frame_bytes(NumberFormat::Fp1220), 54u);
  EXPECT_EQ(configured_frame_bytes(NumberFormat::Fp1632), 66u);
  EXPECT_EQ(configured_frame_bytes(NumberFormat::Float64), 78u);
  EXPECT_EQ(least_baud_for(54, 400), 460800u);
  EXPECT_EQ(least_baud_for(54, 200), 230400u);
  EXPECT_EQ(least_baud_for(54, 100), 115200u);
  EXPECT_EQ(least_baud_for(78, 400), 921600u);
  EXPECT_EQ(baud_problem(460800, 54, 400), "");
  EXPECT_EQ(baud_problem(230400, 54, 400), "54-byte frames at 400 Hz need at least 460800 baud, not 230400");
}

TEST(Commands, RepliesAreParsed) {
  EXPECT_EQ(parse_device_id(Bytes{0x03, 0x70, 0x01, 0x23}), 0x03700123u);
  EXPECT_FALSE(parse_device_id(Bytes{0x03, 0x70}));
  const auto fw = parse_firmware_revision(Bytes{1, 2, 3});
  ASSERT_TRUE(fw);
  EXPECT_EQ(fw->text(), "1.2.3");
  EXPECT_FALSE(parse_firmware_revision(Bytes{1, 2}));
  const std::string code = "MTi-30-2A8G4";
  Bytes padded(code.begin(), code.end());
  padded.insert(padded.end(), {' ', ' ', 0, 0});
  EXPECT_EQ(parse_product_code(padded), code);
}

TEST(Commands, SensorRangesFromTheProductCode) {
  const SensorRanges mti30 = ranges_from_product_code("MTi-30-2A8G4");
  ASSERT_TRUE(mti30.gyro_rad_s && mti30.accel_m_s2);
  EXPECT_NEAR(*mti30.gyro_rad_s, 450 * kDeg, 1e-12);
  EXPECT_NEAR(*mti30.accel_m_s2, 20 * 9.80665, 1e-12);
  EXPECT_NEAR(*ranges_from_product_code("MTi-300-2A8G0").gyro_rad_s, 1000 * kDeg, 1e-12);
  EXPECT_NEAR(*ranges_from_product_code("MTi-G-710-2A5G4").accel_m_s2, 5 * 9.80665, 1e-12);
  EXPECT_FALSE(ranges_from_product_code("MTi-30").gyro_rad_s);
  EXPECT_FALSE(ranges_from_product_code("MTi-30-2A8G9").gyro_rad_s);
  EXPECT_FALSE(ranges_from_product_code("").accel_m_s2);
}

TEST(Commands, ErrorCodesHaveNames) {
  EXPECT_EQ(error_code_name(3), "period invalid");
  EXPECT_EQ(error_code_name(4), "message invalid");
  EXPECT_EQ(error_code_name(30), "timer overflow");
  EXPECT_EQ(error_code_name(32), "baud rate invalid");
  EXPECT_EQ(error_code_name(33), "parameter invalid");
  EXPECT_EQ(error_code_name(40), "device error");
  EXPECT_EQ(describe_error(Bytes{32}), "error 32 (baud rate invalid)");
  EXPECT_EQ(describe_error(Bytes{99}), "error 99 (unknown error)");
  EXPECT_EQ(describe_error({}), "error without a code");
}

TEST(OutputConfiguration, TheImuOutputsWeAskFor) {
  const auto settings = imu_output_configuration(400, NumberFormat::Fp1220);
  EXPECT_EQ(settings, (std::vector<OutputSetting>{{xdi::kPacketCounter, 0xFFFF},
                                                  {xdi::kSampleTimeFine, 0xFFFF},
                                                  {0x4021, 400},
                                                  {0x8021, 400},
                                                  {xdi::kStatusWord, 0xFFFF}}));
  EXPECT_EQ(parse_output_configuration(encode_output_configuration(settings)), settings);
  EXPECT_THROW(parse_output_configuration(Bytes{0x10, 0x20, 0xFF}), std::invalid_argument);
  EXPECT_EQ(describe(OutputSetting{0xA010, 5}), "XDI 0xA010@5Hz");
}

}  // namespace
}  // namespace tumble::mti
