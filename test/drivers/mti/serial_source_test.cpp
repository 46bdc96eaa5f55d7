// The serial source on a pseudo-terminal with a fake MTi on the other side.
// Everything runs on one io_context driven in bounded run_for slices.
#include "drivers/mti/serial_source.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "drivers/mti/imu_recording_reader.hpp"
#include "drivers/mti/imu_recording_writer.hpp"
#include "test/drivers/mti/pty_device.hpp"

namespace tumble::mti {
namespace {

using test_util::PtyDevice;
using test_util::run_until;

SerialSourceOptions options_for(const std::string& device, bool configure) {
  SerialSourceOptions o;
  o.device = device;
  o.configurator.configure = configure;
  o.reconnect_min_s = 0.01;
  o.reconnect_max_s = 0.05;
  return o;
}

std::string temp_name(const std::string& what) {
  return (std::filesystem::temp_directory_path() /
          ("tumble_mti_" + what + "_" + std::to_string(::getpid())))
      .string();
}

TEST(SerialSource, ConfiguresTheDeviceThenDeliversSamples) {
  boost::asio::io_context io;
  PtyDevice device(io);
  std::vector<ImuSample> samples;
  // Under load a reply can be handled after the 100 ms (GoToConfig) or 500 ms
  // retry is due: the command is then sent twice, rightly, and a timeout would
  // reconnect. Retries are tested in ASilentDeviceFailsConfigurationAndIsRetried;
  // here they are put out of reach so the exact command sequence is certain.
  SerialSourceOptions options = options_for(device.slave_path(), true);
  options.configurator.go_to_config_retry_s = options.configurator.reply_retry_s = 60;
  options.configurator.go_to_config_timeout_s = options.configurator.reply_timeout_s = 60;
  SerialSource source(io, options, [&](const ImuSample& s) { samples.push_back(s); });
  source.start();
  ASSERT_TRUE(run_until(io, [&] { return device.measuring() && source.config_step() == ConfigStep::Measuring; }));
  EXPECT_EQ(device.commands(), (std::vector<std::uint8_t>{mid::kGoToConfig, mid::kReqDeviceId, mid::kReqProductCode,
                                                          mid::kReqFirmwareRev, mid::kSetOutputConfiguration,
                                                          mid::kGoToMeasurement}));
  EXPECT_EQ(source.device().product_code, "MTi-30-2A8G4");
  EXPECT_EQ(source.device().device_id, 0x03700123u);
  device.stream(0, 10);
  ASSERT_TRUE(run_until(io, [&] { return samples.size() == 9; }));
  EXPECT_EQ(source.stats().stale_samples_dropped, 1u);  // the first after GoToMeasurement
  EXPECT_EQ(samples.front().gyro_rad_s.x(), static_cast<double>(0.001f));
  // The pty delivers a burst at once, so only the order of times is certain here.
  for (std::size_t i = 1; i < samples.size(); ++i) EXPECT_GT(samples[i].t_s, samples[i - 1].t_s);
  EXPECT_EQ(source.connects(), 1u);
  EXPECT_EQ(source.disconnects(), 0u);
}

TEST(SerialSource, ReadOnlySendsNothing) {
  boost::asio::io_context io;
  PtyDevice device(io);
  std::vector<ImuSample> samples;
  SerialSource source(io, options_for(device.slave_path(), false), [&](const ImuSample& s) { samples.push_back(s); });
  source.start();
  ASSERT_TRUE(source.connected());
  device.stream(0, 10);
  ASSERT_TRUE(run_until(io, [&] { return samples.size() == 10; }));
  EXPECT_EQ(source.config_step(), ConfigStep::ReadOnly);
  EXPECT_EQ(device.bytes_received(), 0u);
}

// The device disappears and comes back on another pty behind the same link
// (as /dev/serial/by-id does): the source notices, backs off, reconnects.
TEST(SerialSource, ReconnectsWhenTheDeviceComesBack) {
  boost::asio::io_context io;
  const std::string link = temp_name("tty_link");
  std::filesystem::remove(link);
  auto device = std::make_unique<PtyDevice>(io);
  std::filesystem::create_symlink(device->slave_path(), link);
  std::vector<ImuSample> samples;
  SerialSource source(io, options_for(link, false), [&](const ImuSample& s) { samples.push_back(s); });
  source.start();
  device->stream(0, 5);
  ASSERT_TRUE(run_until(io, [&] { return samples.size() == 5; }));

  // The link goes first: a pts number, once free, may go to another process's pty.
  std::filesystem::remove(link);
  device->close();
  ASSERT_TRUE(run_until(io, [&] { return source.disconnects() == 1; }));
  EXPECT_FALSE(source.connected());
  EXPECT_FALSE(source.last_error().empty());
  device = std::make_unique<PtyDevice>(io);
  std::filesystem::create_symlink(device->slave_path(), link);
  ASSERT_TRUE(run_until(io, [&] { return source.connects() == 2; }));
  device->stream(100, 5);
  ASSERT_TRUE(run_until(io, [&] { return samples.size() == 10; }));
  source.stop();
  std::filesystem::remove(link);
}

TEST(SerialSource, ASilentDeviceFailsConfigurationAndIsRetried) {
  boost::asio::io_context io;
  PtyDevice device(io);
  device.answer_commands(false);
  SerialSourceOptions options = options_for(device.slave_path(), true);
  options.configurator.go_to_config_timeout_s = 0.2;
  SerialSource source(io, options, [](const ImuSample&) {});
  source.start();
  ASSERT_TRUE(run_until(io, [&] { return source.connects() >= 2; }));
  EXPECT_GE(source.disconnects(), 1u);
  EXPECT_NE(source.last_error().find("no GoToConfigAck"), std::string::npos) << source.last_error();
  // Retried every 100 ms while waiting: at least the first and one more.
  EXPECT_GE(std::count(device.commands().begin(), device.commands().end(), mid::kGoToConfig), 2);
}

TEST(SerialSource, AMissingDeviceIsRetriedWithBackOff) {
  boost::asio::io_context io;
  SerialSource source(io, options_for("/nonexistent/ttyMTi", false), [](const ImuSample&) {});
  source.start();
  EXPECT_FALSE(source.connected());
  EXPECT_NE(source.last_error().find("/nonexistent/ttyMTi"), std::string::npos);
  EXPECT_EQ(source.backoff_s(), 0.02);  // the first retry waits 0.01 s, the next twice that
  ASSERT_TRUE(run_until(io, [&] { return source.failed_opens() >= 4; }));
  EXPECT_EQ(source.backoff_s(), 0.05);  // doubled up to the maximum
  EXPECT_EQ(source.connects(), 0u);
}

// What the live source records replays to the same samples at the same times.
TEST(SerialSource, RecordedReadsReplayToTheSameSamples) {
  const std::string path = temp_name("record.pcap");
  std::vector<ImuSample> live;
  {
    boost::asio::io_context io;
    PtyDevice device(io);
    ImuRecordingWriter writer(path);
    SerialSource source(io, options_for(device.slave_path(), false), [&](const ImuSample& s) { live.push_back(s); });
    source.set_read_handler([&](std::int64_t t_ns, std::span<const std::uint8_t> bytes) { writer.write(t_ns, bytes); });
    source.start();
    for (int burst = 0; burst < 4; ++burst) {
      device.stream(burst * 5, 5);
      ASSERT_TRUE(run_until(io, [&] { return live.size() == static_cast<std::size_t>(5 * (burst + 1)); }));
    }
  }
  ImuRecordingReader reader(path, MtiStreamOptions{});
  EXPECT_EQ(reader.format(), RecordingFormat::Pcap);
  std::vector<ImuSample> replayed;
  while (reader.next(replayed)) {
  }
  ASSERT_EQ(replayed.size(), live.size());
  for (std::size_t i = 0; i < live.size(); ++i) {
    EXPECT_EQ(replayed[i].t_s, live[i].t_s);
    EXPECT_EQ(replayed[i].gyro_rad_s, live[i].gyro_rad_s);
  }
  EXPECT_EQ(reader.problem(), "");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace tumble::mti
