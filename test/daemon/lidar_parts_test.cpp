// The lidar decoder behind the daemon's seam: datagrams from another sender
// than the lidar (lidar.source_ip, or the first sender), or to another port,
// are ignored, counted and reported (rate-limited); the lidar's own are decoded.
#include "daemon/lidar_parts.hpp"

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "drivers/rs16/difop_encode.hpp"
#include "drivers/rs16/laser_geometry.hpp"
#include "drivers/rs16/msop_encode.hpp"
#include "test/daemon/captured_log.hpp"

namespace tumble::daemon {
namespace {

std::array<std::uint8_t, 1248> msop_packet() {
  rs16::MsopPacketData data;
  data.utc_time_ns = 1'622'030'400'000'000'000;  // 2021-05-26
  for (std::size_t b = 0; b < data.blocks.size(); ++b) {
    data.blocks[b].azimuth_deg = 0.4 * static_cast<double>(b);
    for (auto& channel : data.blocks[b].channels) channel = {5.0, 100};
  }
  return rs16::encode_msop(data);
}

TEST(Rs16LidarDecoder, IgnoresCountsAndReportsDatagramsFromAnotherSender) {
  const CapturedLog log;
  LidarConfig config;
  config.source_ip = "192.168.1.200";
  Rs16LidarDecoder decoder(config);
  const std::array<std::uint8_t, 1248> packet = msop_packet();
  PipelineCounters counters;
  PointBlock block;

  LidarDatagram lidar{1.0, rs16::parse_ipv4("192.168.1.200"), 6699, 6699, packet};
  EXPECT_TRUE(decoder.decode(lidar, block));
  EXPECT_EQ(block.all_points().size(), 12u * 32u);

  LidarDatagram stranger = lidar;
  stranger.src_ip = rs16::parse_ipv4("192.168.1.77");
  for (int i = 0; i < 5; ++i) {
    stranger.arrival_s = 1.1 + 0.01 * i;
    EXPECT_FALSE(decoder.decode(stranger, block));
  }
  LidarDatagram wrong_port = lidar;
  wrong_port.dst_port = 5000;
  EXPECT_FALSE(decoder.decode(wrong_port, block));

  decoder.report(counters);
  EXPECT_EQ(counters.lidar_packets.load(), 1);
  EXPECT_EQ(counters.lidar_foreign_packets.load(), 6);
  const std::string text = log.text();
  EXPECT_NE(text.find("warning lidar: ignoring datagrams from 192.168.1.77 to port 6699 "
                      "(the lidar is 192.168.1.200 (lidar.source_ip), ports 6699/7788); 1 so far"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("2 so far"), std::string::npos) << "not rate-limited:\n" << text;
}

// What the recorder keeps: the lidar's datagrams, DIFOP included, and no other.
TEST(Rs16LidarDecoder, SaysWhetherTheLastDatagramCameFromTheLidar) {
  const CapturedLog log;
  Rs16LidarDecoder decoder(LidarConfig{});  // no source_ip: the first sender of a good MSOP datagram
  const std::array<std::uint8_t, 1248> packet = msop_packet();
  PointBlock block;
  const LidarDatagram lidar{1.0, rs16::parse_ipv4("10.0.0.5"), 6699, 6699, packet};
  decoder.decode(lidar, block);
  EXPECT_TRUE(decoder.last_from_the_lidar());
  LidarDatagram difop = lidar;
  difop.dst_port = 7788;
  decoder.decode(difop, block);
  EXPECT_TRUE(decoder.last_from_the_lidar());
  LidarDatagram stranger = lidar;
  stranger.src_ip = rs16::parse_ipv4("10.0.0.6");
  decoder.decode(stranger, block);
  EXPECT_FALSE(decoder.last_from_the_lidar());
  LidarDatagram wrong_port = lidar;
  wrong_port.dst_port = 5000;
  decoder.decode(wrong_port, block);
  EXPECT_FALSE(decoder.last_from_the_lidar());
}

TEST(Rs16LidarDecoder, WithoutASourceIpAnySenderIsTheLidar) {
  Rs16LidarDecoder decoder(LidarConfig{});
  const std::array<std::uint8_t, 1248> packet = msop_packet();
  PointBlock block;
  EXPECT_TRUE(decoder.decode(LidarDatagram{1.0, rs16::parse_ipv4("10.0.0.9"), 6699, 6699, packet}, block));
}

TEST(Rs16LidarDecoder, WithoutASourceIpASecondHostNeverBecomesTheLidarHoweverFastItSends) {
  const CapturedLog log;
  Rs16LidarDecoder decoder(LidarConfig{});
  const std::array<std::uint8_t, 1248> packet = msop_packet();
  PointBlock block;
  PipelineCounters counters;
  const std::uint32_t lidar = rs16::parse_ipv4("192.168.1.200"), other = rs16::parse_ipv4("192.168.1.201");
  // The lidar at 750 packets/s; from 1 s on a second host at 1.5 times that, for 3 s.
  int from_lidar = 0, decoded_from_lidar = 0, from_other = 0;
  for (int i = 0; i < 4 * 750; ++i) {
    const double t_s = 10.0 + i / 750.0;
    from_lidar += 1;
    decoded_from_lidar += decoder.decode(LidarDatagram{t_s, lidar, 6699, 6699, packet}, block);
    if (i < 750) continue;
    for (int k = 0; k < (i % 2 == 0 ? 2 : 1); ++k, ++from_other)
      EXPECT_FALSE(decoder.decode(LidarDatagram{t_s + 0.0001 * k, other, 6699, 6699, packet}, block)) << i;
  }
  EXPECT_EQ(decoded_from_lidar, from_lidar);
  decoder.report(counters);
  EXPECT_EQ(counters.lidar_foreign_packets.load(), from_other);
  EXPECT_NEAR(counters.lidar_foreign_rate_hz.load(), 1125.0, 2.0);
  const std::string text = log.text();
  EXPECT_NE(text.find("info lidar: the lidar is 192.168.1.200, the first sender of MSOP datagrams"), std::string::npos)
      << text;
  EXPECT_NE(text.find("warning lidar: ignoring datagrams from 192.168.1.201 to port 6699 (the lidar is "
                      "192.168.1.200 (the first sender), ports 6699/7788); 1 so far"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("the lidar is 192.168.1.201"), std::string::npos) << text;
}

TEST(Rs16LidarDecoder, WithoutASourceIpOnlyAWellFormedMsopDatagramChoosesTheLidar) {
  Rs16LidarDecoder decoder(LidarConfig{});
  const std::array<std::uint8_t, 1248> packet = msop_packet();
  const std::array<std::uint8_t, 40> garbage{};
  PointBlock block;
  const std::uint32_t noisy = rs16::parse_ipv4("10.0.0.5"), lidar = rs16::parse_ipv4("10.0.0.9");
  EXPECT_FALSE(decoder.decode(LidarDatagram{1.0, noisy, 6699, 6699, garbage}, block));
  EXPECT_TRUE(decoder.decode(LidarDatagram{1.001, lidar, 6699, 6699, packet}, block));
  EXPECT_FALSE(decoder.decode(LidarDatagram{1.002, noisy, 6699, 6699, packet}, block));
}

TEST(Rs16LidarDecoder, ADifopThatDisagreesLaterIsWarnedAboutOnceAndCounted) {
  const CapturedLog log;
  Rs16LidarDecoder decoder(LidarConfig{});
  PointBlock block;
  rs16::DifopData first;
  first.vertical_angles_deg = rs16::kDesignVerticalAnglesDeg;
  rs16::DifopData other = first;
  other.motor_rpm = 1200;
  const auto first_bytes = rs16::encode_difop(first), other_bytes = rs16::encode_difop(other);
  const std::uint32_t lidar = rs16::parse_ipv4("192.168.1.200");
  EXPECT_FALSE(decoder.decode(LidarDatagram{1.0, lidar, 7788, 7788, first_bytes}, block));
  for (int i = 0; i < 4; ++i)
    EXPECT_FALSE(decoder.decode(LidarDatagram{2.0 + i, lidar, 7788, 7788, other_bytes}, block));
  PipelineCounters counters;
  decoder.report(counters);
  EXPECT_EQ(counters.lidar_difop_ignored.load(), 4);
  const std::string text = log.text();
  const std::string warning = "warning rs16: a DIFOP disagrees with the sensor configuration in use (motor speed)";
  EXPECT_NE(text.find(warning), std::string::npos) << text;
  EXPECT_EQ(text.find(warning, text.find(warning) + 1), std::string::npos) << "more than once:\n" << text;
  EXPECT_EQ(text.find("motor speed 1200 rpm"), std::string::npos) << text;
}

TEST(LiveLidarSource, WarnsWhenTheKernelGrantsLessReceiveBufferThanConfigured) {
  std::ifstream rmem_max("/proc/sys/net/core/rmem_max");
  int cap = 0;
  rmem_max >> cap;
  if (cap <= 0 || cap > (1 << 29)) GTEST_SKIP() << "net.core.rmem_max unreadable or too large to exceed";
  const CapturedLog log;
  boost::asio::io_context io;
  LidarConfig config;
  config.bind_address = "127.0.0.1";
  config.msop_port = config.difop_port = 0;  // any free ports
  config.receive_buffer_bytes = cap / 2;
  { const LiveLidarSource enough(io, config); }
  EXPECT_EQ(log.text().find("granted"), std::string::npos) << log.text();
  config.receive_buffer_bytes = 2 * cap;
  { const LiveLidarSource capped(io, config); }
  EXPECT_NE(log.text().find("warning lidar: the kernel granted " + std::to_string(cap / 1024) +
                            " KiB of socket receive buffer, below lidar.receive_buffer_bytes"),
            std::string::npos)
      << log.text();
}

}  // namespace
}  // namespace tumble::daemon
