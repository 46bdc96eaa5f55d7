// The lidar decoder behind the daemon's seam: datagrams from another sender
// than lidar.source_ip, or to another port, are ignored, counted and
// reported (rate-limited); the lidar's own are decoded.
#include "daemon/lidar_parts.hpp"

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <memory>
#include <sstream>
#include <string>

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
                      "(lidar.source_ip 192.168.1.200, ports 6699/7788); 1 so far"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("2 so far"), std::string::npos) << "not rate-limited:\n" << text;
}

TEST(Rs16LidarDecoder, WithoutASourceIpAnySenderIsTheLidar) {
  Rs16LidarDecoder decoder(LidarConfig{});
  const std::array<std::uint8_t, 1248> packet = msop_packet();
  PointBlock block;
  EXPECT_TRUE(decoder.decode(LidarDatagram{1.0, rs16::parse_ipv4("10.0.0.9"), 6699, 6699, packet}, block));
}

TEST(Rs16LidarDecoder, WithoutASourceIpTheBusiestSenderIsTheLidarAndTheOthersForeign) {
  const CapturedLog log;
  Rs16LidarDecoder decoder(LidarConfig{});
  const std::array<std::uint8_t, 1248> packet = msop_packet();
  PointBlock block;
  PipelineCounters counters;
  const std::uint32_t lidar = rs16::parse_ipv4("192.168.1.200"), other = rs16::parse_ipv4("192.168.1.201");
  // Another sensor sends every tenth datagram to the lidar's port.
  int decoded = 0, from_other = 0;
  for (int i = 0; i < 200; ++i) {
    const bool is_other = i % 10 == 9;
    from_other += is_other;
    const bool ok = decoder.decode(LidarDatagram{1.0 + 0.0013 * i, is_other ? other : lidar, 6699, 6699, packet}, block);
    EXPECT_TRUE(!is_other || !ok) << i;
    decoded += ok;
  }
  EXPECT_EQ(decoded, 200 - from_other);
  decoder.report(counters);
  EXPECT_EQ(counters.lidar_foreign_packets.load(), from_other);
  EXPECT_NE(log.text().find("ignoring datagrams from 192.168.1.201 to port 6699 (lidar.source_ip not set, the lidar "
                            "is the busiest sender 192.168.1.200"),
            std::string::npos)
      << log.text();
}

}  // namespace
}  // namespace tumble::daemon
