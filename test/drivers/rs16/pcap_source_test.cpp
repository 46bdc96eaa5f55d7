// Replaying recordings: every link type tcpdump may have used, other traffic
// counted and skipped, other senders dropped, bad files reported clearly.
#include "drivers/rs16/pcap_source.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include "drivers/pcap/udp_frame.hpp"
#include "drivers/rs16/difop_encode.hpp"
#include "drivers/rs16/driver.hpp"
#include "drivers/rs16/recording_writer.hpp"
#include "test/drivers/rs16/packet_stream.hpp"

namespace tumble::rs16 {
namespace {

constexpr std::uint32_t kLidarIp = 0xC0A801C8;
constexpr std::uint32_t kHostIp = 0xC0A80166;
constexpr std::int64_t kCaptureStartNs = 1'704'067'200'000'000'000;

class TempFile {
 public:
  explicit TempFile(const std::string& name)
      : path_((std::filesystem::temp_directory_path() /
               ("tumble_rs16_" + std::to_string(::getpid()) + "_" + name))
                  .string()) {}
  ~TempFile() { std::filesystem::remove(path_); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::vector<std::uint8_t> msop_payload(int index) {
  const auto bytes = encode_msop(test::stream_packet({}, index));
  return {bytes.begin(), bytes.end()};
}

// The Ethernet frame's IPv4 packet (from byte 14) under another link header.
std::vector<std::uint8_t> relink(int link_type, const std::vector<std::uint8_t>& ethernet) {
  std::vector<std::uint8_t> header;
  switch (link_type) {
    case pcap::kLinkLinuxSll:
      header = {0, 0, 0, 1, 0, 6, 2, 0, 0, 0, 0, 0, 0, 1, 0x08, 0x00};
      break;
    case pcap::kLinkLinuxSll2:
      header = {0x08, 0x00, 0, 0, 0, 0, 0, 2, 0, 1, 0, 6, 2, 0, 0, 0, 0, 1, 0, 0};
      break;
    case pcap::kLinkEthernet:  // the same MACs, with an 802.1Q tag
      header = {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x02, 0x00, 0xC0, 0xA8, 0x01, 0xC8, 0x81, 0x00, 0x00, 0x05, 0x08, 0x00};
      break;
    default:
      break;  // raw IPv4: nothing in front
  }
  std::vector<std::uint8_t> out(header.size() + ethernet.size() - 14);
  std::copy(header.begin(), header.end(), out.begin());
  std::copy(ethernet.begin() + 14, ethernet.end(), out.begin() + static_cast<std::ptrdiff_t>(header.size()));
  return out;
}

TEST(Rs16PcapSource, ReadsEveryLinkTypeTcpdumpUses) {
  for (const int link : {pcap::kLinkEthernet, pcap::kLinkLinuxSll, pcap::kLinkLinuxSll2, pcap::kLinkRawIpv4,
                         pcap::kDltRaw}) {
    TempFile file("link" + std::to_string(link) + ".pcap");
    {
      pcap::Writer w(file.path(), link);
      for (int i = 0; i < 3; ++i)
        w.write(kCaptureStartNs + i * 1'332'000,
                relink(link, pcap::make_udp_ethernet_frame(kLidarIp, kHostIp, 6699, 6699, msop_payload(i))));
      const auto difop = encode_difop(DifopData{});
      w.write(kCaptureStartNs + 5'000'000, relink(link, pcap::make_udp_ethernet_frame(kLidarIp, kHostIp, 7788, 7788, difop)));
    }
    PcapSource source(file.path(), {});
    for (int i = 0; i < 3; ++i) {
      const auto d = source.next();
      ASSERT_TRUE(d) << "link type " << link;
      EXPECT_EQ(d->kind, PacketKind::Msop);
      EXPECT_EQ(d->source_ip, kLidarIp);
      EXPECT_NEAR(d->arrival_s, (kCaptureStartNs + i * 1'332'000) * 1e-9, 1e-6);
      EXPECT_EQ(std::vector<std::uint8_t>(d->payload.begin(), d->payload.end()), msop_payload(i));
    }
    const auto difop = source.next();
    ASSERT_TRUE(difop);
    EXPECT_EQ(difop->kind, PacketKind::Difop);
    EXPECT_FALSE(source.next());
    EXPECT_FALSE(source.truncated());
    EXPECT_EQ(source.stats().msop, 3u);
    EXPECT_EQ(source.stats().difop, 1u);
  }
}

TEST(Rs16PcapSource, ReadsPcapng) {
  // One section, one Ethernet interface, one enhanced packet block.
  const auto frame = pcap::make_udp_ethernet_frame(kLidarIp, kHostIp, 6699, 6699, msop_payload(0));
  std::vector<std::uint8_t> file;
  auto u32 = [&](std::uint32_t v) {
    for (int i = 0; i < 4; ++i) file.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  auto u16 = [&](std::uint16_t v) {
    file.push_back(static_cast<std::uint8_t>(v & 0xFF));
    file.push_back(static_cast<std::uint8_t>(v >> 8));
  };
  u32(0x0A0D0D0A), u32(28), u32(0x1A2B3C4D), u16(1), u16(0), u32(0xFFFFFFFF), u32(0xFFFFFFFF), u32(28);  // SHB
  u32(1), u32(20), u16(1), u16(0), u32(65535), u32(20);                                                    // IDB
  const std::uint32_t padded = static_cast<std::uint32_t>((frame.size() + 3) / 4 * 4);
  const std::uint64_t t_us = static_cast<std::uint64_t>(kCaptureStartNs / 1000);
  u32(6), u32(32 + padded), u32(0), u32(static_cast<std::uint32_t>(t_us >> 32)),
      u32(static_cast<std::uint32_t>(t_us)), u32(static_cast<std::uint32_t>(frame.size())),
      u32(static_cast<std::uint32_t>(frame.size()));
  file.insert(file.end(), frame.begin(), frame.end());
  file.resize(file.size() + (padded - frame.size()), 0);
  u32(32 + padded);
  TempFile path("ng.pcapng");
  std::ofstream(path.path(), std::ios::binary).write(reinterpret_cast<const char*>(file.data()),
                                                      static_cast<std::streamsize>(file.size()));
  PcapSource source(path.path(), {});
  const auto d = source.next();
  ASSERT_TRUE(d);
  EXPECT_EQ(d->kind, PacketKind::Msop);
  EXPECT_NEAR(d->arrival_s, kCaptureStartNs * 1e-9, 1e-6);
  EXPECT_EQ(d->payload.size(), 1248u);
}

TEST(Rs16PcapSource, OtherTrafficIsCountedAndSkipped) {
  TempFile file("other.pcap");
  {
    pcap::Writer w(file.path(), pcap::kLinkEthernet);
    const std::vector<std::uint8_t> dns(40, 0x11);
    w.write(kCaptureStartNs, pcap::make_udp_ethernet_frame(0x0A000001, 0x0A000002, 5353, 53, dns));  // other port
    auto tcp = pcap::make_udp_ethernet_frame(kLidarIp, kHostIp, 6699, 6699, msop_payload(0));
    tcp[14 + 9] = 6;  // protocol TCP
    w.write(kCaptureStartNs + 1, tcp);
    auto arp = pcap::make_udp_ethernet_frame(kLidarIp, kHostIp, 6699, 6699, msop_payload(0));
    arp[12] = 0x08;
    arp[13] = 0x06;  // EtherType ARP
    w.write(kCaptureStartNs + 2, arp);
    w.write(kCaptureStartNs + 3, std::vector<std::uint8_t>(10, 0));  // runt
    w.write(kCaptureStartNs + 4, pcap::make_udp_ethernet_frame(0x0A000009, kHostIp, 6699, 6699, msop_payload(0)));  // other sender
    w.write(kCaptureStartNs + 5, pcap::make_udp_ethernet_frame(kLidarIp, kHostIp, 6699, 6699, msop_payload(0)));
  }
  SourceConfig config;
  config.source_ip = kLidarIp;
  PcapSource source(file.path(), config);
  const auto d = source.next();
  ASSERT_TRUE(d);
  EXPECT_EQ(d->source_ip, kLidarIp);
  EXPECT_FALSE(source.next());
  EXPECT_EQ(source.stats().records, 6u);
  EXPECT_EQ(source.stats().other_port, 1u);
  EXPECT_EQ(source.stats().not_udp, 3u);
  EXPECT_EQ(source.stats().wrong_source, 1u);
  EXPECT_EQ(source.stats().msop, 1u);
}

TEST(Rs16PcapSource, PortsAreConfigurable) {
  TempFile file("ports.pcap");
  {
    pcap::Writer w(file.path(), pcap::kLinkEthernet);
    w.write(kCaptureStartNs, pcap::make_udp_ethernet_frame(kLidarIp, kHostIp, 6699, 6699, msop_payload(0)));
    w.write(kCaptureStartNs + 1, pcap::make_udp_ethernet_frame(kLidarIp, kHostIp, 6699, 2368, msop_payload(1)));
  }
  SourceConfig config;
  config.msop_port = 2368;
  PcapSource source(file.path(), config);
  const auto d = source.next();
  ASSERT_TRUE(d);
  EXPECT_EQ(std::vector<std::uint8_t>(d->payload.begin(), d->payload.end()), msop_payload(1));
  EXPECT_EQ(source.stats().other_port, 1u);
  config.difop_port = 2368;
  EXPECT_THROW(PcapSource(file.path(), config), std::invalid_argument);
}

TEST(Rs16PcapSource, TruncatedRecordingSaysWhereAndKeepsWhatCameBefore) {
  TempFile file("truncated.pcap");
  {
    RecordingWriter w(file.path());
    for (int i = 0; i < 5; ++i) w.write(kCaptureStartNs + i * 1'332'000, PacketKind::Msop, msop_payload(i));
  }
  std::filesystem::resize_file(file.path(), std::filesystem::file_size(file.path()) - 600);
  PcapSource source(file.path(), {});
  int n = 0;
  while (source.next()) ++n;
  EXPECT_EQ(n, 4);
  ASSERT_TRUE(source.truncated());
  EXPECT_NE(source.error().find(file.path()), std::string::npos) << source.error();
  EXPECT_NE(source.error().find("truncated"), std::string::npos) << source.error();
  EXPECT_NE(source.error().find("record 4"), std::string::npos) << source.error();
}

TEST(Rs16PcapSource, NotAPcapOrWrongLinkTypeThrowsNamingTheFile) {
  TempFile garbage("garbage.pcap");
  std::ofstream(garbage.path()) << "\x55\xAA\x05\x0A this is an MSOP magic, not a pcap magic";
  try {
    PcapSource source(garbage.path(), {});
    FAIL() << "no exception";
  } catch (const pcap::Error& e) {
    EXPECT_NE(std::string(e.what()).find(garbage.path()), std::string::npos) << e.what();
  }
  TempFile user0("imu.pcap");
  { pcap::Writer w(user0.path(), pcap::kLinkUser0); }
  try {
    PcapSource source(user0.path(), {});
    FAIL() << "no exception";
  } catch (const pcap::Error& e) {
    EXPECT_NE(std::string(e.what()).find("link type 147"), std::string::npos) << e.what();
  }
}

TEST(Rs16PcapSource, BadLidarPacketsInARecordingAreCountedByTheDriver) {
  TempFile file("badpackets.pcap");
  {
    RecordingWriter w(file.path());
    auto wrong_magic = msop_payload(0);
    wrong_magic[0] = 0x00;
    w.write(kCaptureStartNs, PacketKind::Msop, wrong_magic);
    w.write(kCaptureStartNs + 1, PacketKind::Msop, std::vector<std::uint8_t>(100, 0x55));
    auto wrong_tail = msop_payload(1);
    wrong_tail[1247] = 0x00;
    w.write(kCaptureStartNs + 2, PacketKind::Msop, wrong_tail);
    w.write(kCaptureStartNs + 3, PacketKind::Difop, msop_payload(2));  // MSOP bytes on the DIFOP port
    w.write(kCaptureStartNs + 4, PacketKind::Msop, msop_payload(3));
  }
  int scans = 0;
  Driver driver({}, [&](Scan&, const ScanReport&) { ++scans; });
  PcapSource source(file.path(), {});
  while (const auto d = source.next()) driver.on_datagram(*d);
  const DecoderStats& s = driver.stats();
  EXPECT_EQ(s.bad_msop.wrong_magic, 1u);
  EXPECT_EQ(s.bad_msop.wrong_size, 1u);
  EXPECT_EQ(s.bad_msop.wrong_tail, 1u);
  EXPECT_EQ(s.bad_difop.wrong_magic, 1u);
  EXPECT_EQ(s.msop_packets, 1u);
  EXPECT_EQ(s.points, 384u);
  EXPECT_EQ(scans, 0);
}

TEST(Rs16SourceConfig, Ipv4AddressesReadAndPrintInHostOrder) {
  EXPECT_EQ(parse_ipv4("192.168.1.200"), kLidarIp);
  EXPECT_EQ(format_ipv4(kLidarIp), "192.168.1.200");
  try {
    parse_ipv4("192.168.1");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("192.168.1"), std::string::npos);
  }
}

TEST(Rs16RecordingWriter, WritesWhatPcapSourceReadsBack) {
  TempFile file("recording.pcap");
  RecordingAddresses addresses;
  addresses.msop_port = 6000;
  addresses.difop_port = 6001;
  const auto difop = encode_difop(DifopData{});
  {
    RecordingWriter w(file.path(), addresses);
    w.write(kCaptureStartNs, PacketKind::Msop, msop_payload(0));
    w.write(kCaptureStartNs + 777, PacketKind::Difop, difop);
    w.flush();
  }
  SourceConfig config;
  config.msop_port = 6000;
  config.difop_port = 6001;
  config.source_ip = addresses.lidar_ip;
  PcapSource source(file.path(), config);
  const auto a = source.next();
  ASSERT_TRUE(a);
  EXPECT_EQ(a->kind, PacketKind::Msop);
  EXPECT_EQ(std::vector<std::uint8_t>(a->payload.begin(), a->payload.end()), msop_payload(0));
  const auto b = source.next();
  ASSERT_TRUE(b);
  EXPECT_EQ(b->kind, PacketKind::Difop);
  EXPECT_NEAR(b->arrival_s, kCaptureStartNs * 1e-9 + 777e-9, 1e-6);
  EXPECT_TRUE(std::equal(difop.begin(), difop.end(), b->payload.begin(), b->payload.end()));
}

}  // namespace
}  // namespace tumble::rs16
