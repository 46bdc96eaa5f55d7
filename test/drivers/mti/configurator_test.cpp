// The configurator against a scripted fake device: bytes out are parsed as
// frames, replies go back in as frames, and time is whatever the test says.
#include "drivers/mti/configurator.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "drivers/mti/commands.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_encode.hpp"
#include "test/drivers/mti/mti_test_util.hpp"

namespace tumble::mti {
namespace {

using Bytes = std::vector<std::uint8_t>;

std::vector<std::uint8_t> mids_of(const Bytes& bytes) {
  std::vector<std::uint8_t> mids;
  for (const auto& f : test_util::read_frames(bytes)) mids.push_back(f.mid);
  return mids;
}

// What the host sent since the last call, as MIDs.
std::vector<std::uint8_t> sent(Configurator& c) { return mids_of(c.take_output()); }

void reply(Configurator& c, std::uint8_t mid, const Bytes& payload, double now_s) {
  c.on_frame(XbusFrame{kBusIdMaster, mid, payload, payload.size() + 5, 0}, now_s);
}

Bytes text(const std::string& s) { return {s.begin(), s.end()}; }

const Bytes kFirmware{1, 8, 2, 0, 0, 0, 37, 0, 1, 0x15, 0x34};

using Mids = std::vector<std::uint8_t>;

// Walks a fresh configurator from start to the SetOutputConfiguration step.
void up_to_output_configuration(Configurator& c, double t = 0) {
  c.start(t);
  ASSERT_EQ(sent(c), Mids{mid::kGoToConfig});
  reply(c, mid::kGoToConfigAck, {}, t + 0.01);
  ASSERT_EQ(sent(c), Mids{mid::kReqDeviceId});
  reply(c, mid::kDeviceId, {0x03, 0x70, 0x01, 0x23}, t + 0.02);
  ASSERT_EQ(sent(c), Mids{mid::kReqProductCode});
  reply(c, mid::kProductCode, text("MTi-30-2A8G4"), t + 0.03);
  ASSERT_EQ(sent(c), Mids{mid::kReqFirmwareRev});
  reply(c, mid::kFirmwareRev, kFirmware, t + 0.04);
}

TEST(Configurator, FullSequenceToMeasurement) {
  Configurator c(ConfiguratorOptions{});
  up_to_output_configuration(c);
  const Bytes set_output = c.take_output();
  EXPECT_EQ(set_output, encode_set_output_configuration(imu_output_configuration(100, NumberFormat::Float32)));
  reply(c, mid::kMtData2, encode_mtdata2(MtData2Out{}), 0.05);  // still streaming: ignored
  EXPECT_EQ(c.step(), ConfigStep::SetOutputConfiguration);
  reply(c, mid::kOutputConfiguration, encode_output_configuration(c.requested_output()), 0.06);
  EXPECT_EQ(sent(c), Mids{mid::kGoToMeasurement});
  EXPECT_FALSE(c.measuring());
  reply(c, mid::kGoToMeasurementAck, {}, 0.07);
  EXPECT_EQ(c.step(), ConfigStep::Measuring);
  EXPECT_TRUE(c.measuring());
  EXPECT_TRUE(c.take_measurement_started());
  EXPECT_FALSE(c.take_measurement_started());
  EXPECT_EQ(c.device().device_id, 0x03700123u);
  EXPECT_EQ(c.device().product_code, "MTi-30-2A8G4");
  EXPECT_EQ(c.device().firmware, "1.8.2 build 37 rev 70964");
  ASSERT_TRUE(c.device().ranges.gyro_rad_s);
  EXPECT_NEAR(*c.device().ranges.gyro_rad_s, 450 * std::numbers::pi / 180, 1e-12);
  EXPECT_TRUE(c.take_output().empty());
  EXPECT_FALSE(c.take_baud_switch());
}

TEST(Configurator, GoToConfigIsRetriedEvery100msForTwoSeconds) {
  Configurator c(ConfiguratorOptions{});
  c.start(10.0);
  int sends = static_cast<int>(sent(c).size());
  for (int ms = 10; ms < 2000; ms += 10) {
    c.on_tick(10.0 + ms / 1000.0);
    sends += static_cast<int>(sent(c).size());
  }
  EXPECT_EQ(sends, 20);
  EXPECT_EQ(c.step(), ConfigStep::GoToConfig);
  c.on_tick(12.0);
  EXPECT_TRUE(c.failed());
  EXPECT_NE(c.error().find("no GoToConfigAck within 2.0 s at 115200 baud"), std::string::npos) << c.error();
}

TEST(Configurator, ALateDuplicateAckIsIgnored) {
  Configurator c(ConfiguratorOptions{});
  c.start(0);
  c.on_tick(0.1);
  reply(c, mid::kGoToConfigAck, {}, 0.11);
  reply(c, mid::kGoToConfigAck, {}, 0.12);  // answer to the retry
  EXPECT_EQ(c.step(), ConfigStep::ReqDeviceId);
}

TEST(Configurator, ASilentStepTimesOutByName) {
  Configurator c(ConfiguratorOptions{});
  c.start(0);
  reply(c, mid::kGoToConfigAck, {}, 0);
  reply(c, mid::kDeviceId, {0, 0, 0, 1}, 0);
  sent(c);
  c.on_tick(0.49);
  EXPECT_TRUE(sent(c).empty());
  c.on_tick(0.5);
  EXPECT_EQ(sent(c), Mids{mid::kReqProductCode});  // resent
  c.on_tick(2.0);
  EXPECT_TRUE(c.failed());
  EXPECT_EQ(c.error(), "no reply to ReqProductCode within 2.0 s");
}

class ConfiguratorError : public ::testing::TestWithParam<std::pair<int, std::string>> {};

TEST_P(ConfiguratorError, IsReportedByName) {
  Configurator c(ConfiguratorOptions{});
  up_to_output_configuration(c);
  reply(c, mid::kError, {static_cast<std::uint8_t>(GetParam().first)}, 0.1);
  EXPECT_TRUE(c.failed());
  EXPECT_EQ(c.error(), "the MTi answered SetOutputConfiguration with error " + std::to_string(GetParam().first) +
                           " (" + GetParam().second + ")");
}

INSTANTIATE_TEST_SUITE_P(Codes, ConfiguratorError,
                         ::testing::Values(std::pair<int, std::string>{3, "period invalid"},
                                           std::pair<int, std::string>{4, "message invalid"},
                                           std::pair<int, std::string>{30, "timer overflow"},
                                           std::pair<int, std::string>{32, "baud rate invalid"},
                                           std::pair<int, std::string>{33, "parameter invalid"},
                                           std::pair<int, std::string>{40, "device error"}));

TEST(Configurator, AnEchoThatDiffersFromTheRequestIsAClearError) {
  ConfiguratorOptions options;
  options.imu_rate_hz = 200;
  options.baud = 230400;
  Configurator c(options);
  up_to_output_configuration(c);
  sent(c);
  auto effective = c.requested_output();
  effective[3].rate_hz = 100;  // the device lowered RateOfTurn
  reply(c, mid::kOutputConfiguration, encode_output_configuration(effective), 0.1);
  EXPECT_TRUE(c.failed());
  EXPECT_EQ(c.error(),
            "the MTi did not take the output configuration: asked PacketCounter@max, SampleTimeFine@max, "
            "Acceleration(Float32)@200Hz, RateOfTurn(Float32)@200Hz, StatusWord@max; it uses PacketCounter@max, "
            "SampleTimeFine@max, Acceleration(Float32)@200Hz, RateOfTurn(Float32)@100Hz, StatusWord@max");
}

TEST(Configurator, WakeUpIsAcknowledgedAndTheSequenceStartsOver) {
  Configurator c(ConfiguratorOptions{});
  up_to_output_configuration(c);
  reply(c, mid::kOutputConfiguration, encode_output_configuration(c.requested_output()), 0.1);
  reply(c, mid::kGoToMeasurementAck, {}, 0.1);
  sent(c);
  ASSERT_TRUE(c.measuring());
  reply(c, mid::kWakeUp, {}, 5.0);  // the device restarted
  EXPECT_EQ(sent(c), (Mids{mid::kWakeUpAck, mid::kGoToConfig}));
  EXPECT_EQ(c.step(), ConfigStep::GoToConfig);
  EXPECT_FALSE(c.measuring());
}

TEST(Configurator, ReadOnlySendsNothingAndTakesWhatComes) {
  ConfiguratorOptions options;
  options.configure = false;
  options.imu_rate_hz = 400;  // not checked against the baud: nothing is configured
  Configurator c(options);
  c.start(0);
  EXPECT_EQ(c.step(), ConfigStep::ReadOnly);
  EXPECT_TRUE(c.measuring());
  reply(c, mid::kWakeUp, {}, 0.1);  // answering would keep the device in config state
  c.on_tick(5.0);
  EXPECT_TRUE(c.take_output().empty());
  EXPECT_FALSE(c.take_measurement_started());
}

TEST(Configurator, OptionsThatCannotWorkAreRefused) {
  ConfiguratorOptions fast;
  fast.imu_rate_hz = 400;
  try {
    Configurator c(fast);
    FAIL() << "400 Hz at 115200 baud accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "mti: 54-byte frames at 400 Hz need at least 460800 baud, not 115200");
  }
  fast.set_baud = 460800;
  EXPECT_NO_THROW(Configurator{fast});
  fast.format = NumberFormat::Float64;
  EXPECT_THROW(Configurator{fast}, std::invalid_argument);  // 78 bytes need 921600
  ConfiguratorOptions bad;
  bad.imu_rate_hz = 0;
  EXPECT_THROW(Configurator{bad}, std::invalid_argument);
  bad.imu_rate_hz = 401;
  EXPECT_THROW(Configurator{bad}, std::invalid_argument);
  ConfiguratorOptions odd_baud;
  odd_baud.set_baud = 250000;
  EXPECT_THROW(Configurator{odd_baud}, std::invalid_argument);
}

TEST(Configurator, BaudChangeResetsTheDeviceAndSwitchesThePort) {
  ConfiguratorOptions options;
  options.imu_rate_hz = 400;
  options.set_baud = 921600;
  Configurator c(options);
  up_to_output_configuration(c);
  EXPECT_EQ(c.take_output(), encode_set_baudrate(921600));
  reply(c, mid::kSetBaudrateAck, {}, 0.1);
  EXPECT_EQ(sent(c), Mids{mid::kReset});
  EXPECT_FALSE(c.take_baud_switch());
  reply(c, mid::kResetAck, {}, 0.2);
  EXPECT_EQ(c.take_baud_switch(), 921600u);
  EXPECT_EQ(c.line_baud(), 921600u);
  EXPECT_EQ(c.step(), ConfigStep::AwaitWakeUp);
  EXPECT_TRUE(sent(c).empty());
  reply(c, mid::kWakeUp, {}, 1.5);
  EXPECT_EQ(sent(c), (Mids{mid::kWakeUpAck, mid::kGoToConfig}));
  reply(c, mid::kGoToConfigAck, {}, 1.6);
  reply(c, mid::kDeviceId, {0, 0, 0, 1}, 1.6);
  reply(c, mid::kProductCode, text("MTi-30-2A8G4"), 1.6);
  reply(c, mid::kFirmwareRev, kFirmware, 1.6);
  EXPECT_EQ(sent(c), (Mids{mid::kReqDeviceId, mid::kReqProductCode, mid::kReqFirmwareRev,
                           mid::kSetOutputConfiguration}));  // no second SetBaudrate
  reply(c, mid::kOutputConfiguration, encode_output_configuration(c.requested_output()), 1.7);
  reply(c, mid::kGoToMeasurementAck, {}, 1.7);
  EXPECT_TRUE(c.measuring());
}

TEST(Configurator, ADeviceThatDoesNotComeBackAfterResetIsAnError) {
  ConfiguratorOptions options;
  options.set_baud = 460800;
  Configurator c(options);
  up_to_output_configuration(c);
  reply(c, mid::kSetBaudrateAck, {}, 0.1);
  reply(c, mid::kResetAck, {}, 0.2);
  c.on_tick(5.3);
  EXPECT_TRUE(c.failed());
  EXPECT_EQ(c.error(), "the MTi did not come back (no WakeUp) within 5.0 s of its reset to 460800 baud");
}

// Set to the new baud in an earlier run, the device is silent at the old one.
TEST(Configurator, ASilentDeviceIsTriedAtTheNewBaud) {
  ConfiguratorOptions options;
  options.set_baud = 460800;
  Configurator c(options);
  c.start(0);
  for (int ms = 100; ms <= 2000; ms += 100) c.on_tick(ms / 1000.0);
  EXPECT_EQ(c.take_baud_switch(), 460800u);
  EXPECT_EQ(c.step(), ConfigStep::GoToConfig);
  EXPECT_FALSE(c.failed());
  sent(c);
  reply(c, mid::kGoToConfigAck, {}, 2.1);
  reply(c, mid::kDeviceId, {0, 0, 0, 1}, 2.1);
  reply(c, mid::kProductCode, text("MTi-30-2A8G4"), 2.1);
  reply(c, mid::kFirmwareRev, kFirmware, 2.1);
  EXPECT_EQ(sent(c).back(), mid::kSetOutputConfiguration);
}

}  // namespace
}  // namespace tumble::mti
