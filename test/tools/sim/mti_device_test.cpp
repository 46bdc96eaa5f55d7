// The simulated MTi against the driver's own configurator, byte for byte and
// without I/O: time is a number stepped here.
#include "tools/sim/mti_device.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <vector>

#include "drivers/mti/commands.hpp"
#include "drivers/mti/configurator.hpp"
#include "drivers/mti/frame_reader.hpp"
#include "drivers/mti/message_ids.hpp"
#include "test/fixtures.hpp"

namespace tumble::sim {
namespace {

constexpr double kStep_s = 0.001;

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Runs the configurator against the device until it measures, fails, or
// max_s passes; returns the time it took.
double handshake(mti::Configurator& host, MtiDevice& device, double max_s) {
  mti::FrameReader reader;
  host.start(0.0);
  double t = 0.0;
  std::vector<std::uint8_t> from_device;
  for (; t < max_s && !host.measuring() && !host.failed(); t += kStep_s) {
    device.on_host_bytes(host.take_output(), t);
    from_device.clear();
    device.take_due(t, from_device);
    reader.push(from_device);
    while (const auto frame = reader.next())
      if (frame->mid != mti::mid::kMtData2) host.on_frame(*frame, t);
    host.on_tick(t);
  }
  return t;
}

TEST(MtiDevice, AnswersTheDriversWholeHandshake) {
  mti::Configurator host(mti::ConfiguratorOptions{});
  MtiDevice device(MtiDeviceOptions{.start = MtiStartState::Config});
  const double took_s = handshake(host, device, 3.0);
  ASSERT_TRUE(host.measuring()) << host.error();
  EXPECT_LT(took_s, 0.1);
  EXPECT_TRUE(device.measuring());
  EXPECT_EQ(host.device().product_code, "MTi-30-2A8G4");
  EXPECT_EQ(host.device().device_id, 0x03700123u);
  EXPECT_EQ(host.device().firmware, "1.8.2 build 37 rev 70964");
  EXPECT_EQ(device.output_configuration(), host.requested_output());
}

TEST(MtiDevice, StopsStreamingOnGoToConfig) {
  mti::Configurator host(mti::ConfiguratorOptions{});
  MtiDevice device(MtiDeviceOptions{.start = MtiStartState::Measuring});
  ASSERT_TRUE(device.measuring());
  device.on_host_bytes(mti::encode_go_to_config(), 0.0);
  std::vector<std::uint8_t> out;
  device.take_due(1.0, out);
  EXPECT_EQ(out, (std::vector<std::uint8_t>{0xFA, 0xFF, 0x31, 0x00, 0xD0}));
  EXPECT_FALSE(device.measuring());
  EXPECT_TRUE(handshake(host, device, 3.0) < 3.0 && host.measuring()) << host.error();
}

TEST(MtiDevice, RefusesConfigurationWhileMeasuring) {
  MtiDevice device(MtiDeviceOptions{.start = MtiStartState::Measuring});
  device.on_host_bytes(mti::encode_req_device_id(), 0.0);
  std::vector<std::uint8_t> out;
  device.take_due(1.0, out);
  EXPECT_EQ(out, (std::vector<std::uint8_t>{0xFA, 0xFF, 0x42, 0x01, 0x04, 0xBA}));  // error 4: message invalid
}

TEST(MtiDevice, EchoesTheLlcpOutputConfigurationExample) {
  TUMBLE_REQUIRE_FIXTURE("mti/llcp-examples/llcp_example_SetOutputConfiguration.bin");
  MtiDevice device(MtiDeviceOptions{.start = MtiStartState::Config});
  device.on_host_bytes(read_bytes(tumble::test::fixture_path("mti/llcp-examples/llcp_example_SetOutputConfiguration.bin")),
                       0.0);
  std::vector<std::uint8_t> out;
  device.take_due(1.0, out);
  EXPECT_EQ(out, read_bytes(tumble::test::fixture_path("mti/llcp-examples/llcp_example_SetOutputConfigurationAck.bin")));
}

TEST(MtiDevice, EchoesTheRateItCanRunSoTheDriverNoticesTheDifference) {
  mti::Configurator host(mti::ConfiguratorOptions{.imu_rate_hz = 30});
  MtiDevice device(MtiDeviceOptions{.start = MtiStartState::Config});
  handshake(host, device, 3.0);
  ASSERT_TRUE(host.failed());
  EXPECT_NE(host.error().find("@30Hz"), std::string::npos) << host.error();
  EXPECT_NE(host.error().find("@25Hz"), std::string::npos) << host.error();
}

TEST(MtiDevice, SilentDeviceTimesTheDriverOut) {
  mti::Configurator host(mti::ConfiguratorOptions{});
  MtiDevice device(MtiDeviceOptions{.silent = true});
  handshake(host, device, 3.0);
  ASSERT_TRUE(host.failed());
  EXPECT_NE(host.error().find("no GoToConfigAck within 2.0 s"), std::string::npos) << host.error();
  EXPECT_FALSE(device.measuring());
}

TEST(MtiDevice, RefusedRequestReachesTheDriverAsDeviceError) {
  mti::Configurator host(mti::ConfiguratorOptions{});
  MtiDevice device(MtiDeviceOptions{.start = MtiStartState::Config, .refuse_mid = mti::mid::kReqFirmwareRev,
                                    .refuse_code = 40});
  handshake(host, device, 3.0);
  ASSERT_TRUE(host.failed());
  EXPECT_EQ(host.error(), "the MTi answered ReqFWRev with error 40 (device error)");
  EXPECT_EQ(device.counts().errors_sent, 1u);
}

TEST(MtiDevice, MovesToANewBaudAfterResetAndWakesUp) {
  mti::Configurator host(mti::ConfiguratorOptions{.set_baud = 460800});
  MtiDevice device(MtiDeviceOptions{.start = MtiStartState::Config});
  handshake(host, device, 5.0);
  ASSERT_TRUE(host.measuring()) << host.error();
  EXPECT_EQ(device.baud(), 460800u);
  EXPECT_EQ(host.line_baud(), 460800u);
}

TEST(MtiDevice, PowerUpMeasuresUnlessTheWakeUpIsAcknowledged) {
  MtiDevice ignored(MtiDeviceOptions{.start = MtiStartState::WakeUp});
  std::vector<std::uint8_t> out;
  ignored.take_due(0.0, out);
  EXPECT_EQ(out, (std::vector<std::uint8_t>{0xFA, 0xFF, 0x3E, 0x00, 0xC3}));
  EXPECT_FALSE(ignored.measuring());
  ignored.take_due(0.6, out);
  EXPECT_TRUE(ignored.measuring());

  MtiDevice acknowledged(MtiDeviceOptions{.start = MtiStartState::WakeUp});
  acknowledged.take_due(0.0, out);
  acknowledged.on_host_bytes(mti::encode_wake_up_ack(), 0.1);
  acknowledged.take_due(0.6, out);
  EXPECT_FALSE(acknowledged.measuring());
}

}  // namespace
}  // namespace tumble::sim
