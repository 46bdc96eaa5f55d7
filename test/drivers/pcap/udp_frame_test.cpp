#include "drivers/pcap/udp_frame.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "drivers/pcap/pcap_file.hpp"
#include "test/fixtures.hpp"

namespace tumble::pcap {
namespace {

constexpr std::uint32_t kSrc = 0xC0A801C8;  // 192.168.1.200
constexpr std::uint32_t kDst = 0xC0A80166;  // 192.168.1.102

std::vector<std::uint8_t> payload_of(std::size_t n) {
  std::vector<std::uint8_t> p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<std::uint8_t>(i * 7);
  return p;
}

std::vector<std::uint8_t> with_header(const std::vector<std::uint8_t>& header, const std::vector<std::uint8_t>& ip) {
  std::vector<std::uint8_t> out(header.size() + ip.size());
  std::copy(header.begin(), header.end(), out.begin());
  std::copy(ip.begin(), ip.end(), out.begin() + static_cast<std::ptrdiff_t>(header.size()));
  return out;
}

void expect_datagram(int link, const std::vector<std::uint8_t>& frame, const std::vector<std::uint8_t>& payload) {
  const auto d = parse_udp_datagram(link, frame);
  ASSERT_TRUE(d) << "link type " << link;
  EXPECT_EQ(d->src_ip, kSrc);
  EXPECT_EQ(d->src_port, 6699);
  EXPECT_EQ(d->dst_port, 7788);
  EXPECT_EQ(std::vector<std::uint8_t>(d->payload.begin(), d->payload.end()), payload) << "link type " << link;
}

TEST(UdpFrame, ParsesEveryLidarLinkType) {
  const auto payload = payload_of(1248);
  const auto eth = make_udp_ethernet_frame(kSrc, kDst, 6699, 7788, payload);
  const std::vector<std::uint8_t> ip(eth.begin() + 14, eth.end());
  const std::vector<std::uint8_t> macs(eth.begin(), eth.begin() + 12);
  expect_datagram(kLinkEthernet, eth, payload);
  auto tagged = macs;
  for (std::uint8_t b : {0x81, 0x00, 0x00, 0x07, 0x08, 0x00}) tagged.push_back(b);
  expect_datagram(kLinkEthernet, with_header(tagged, ip), payload);
  auto double_tagged = macs;
  for (std::uint8_t b : {0x88, 0xA8, 0x00, 0x01, 0x81, 0x00, 0x00, 0x07, 0x08, 0x00}) double_tagged.push_back(b);
  expect_datagram(kLinkEthernet, with_header(double_tagged, ip), payload);
  expect_datagram(kLinkLinuxSll, with_header({0, 0, 0, 1, 0, 6, 2, 0, 0, 0, 0, 0, 0, 1, 0x08, 0x00}, ip), payload);
  expect_datagram(kLinkLinuxSll2, with_header({0x08, 0x00, 0, 0, 0, 0, 0, 2, 0, 1, 0, 6, 2, 0, 0, 0, 0, 1, 0, 0}, ip),
                  payload);
  expect_datagram(kLinkRawIpv4, ip, payload);
  expect_datagram(kLinkRaw, ip, payload);
  expect_datagram(kDltRaw, ip, payload);
}

TEST(UdpFrame, RejectsWhatIsNotAWholeUdpHeaderOverIpv4) {
  const auto eth = make_udp_ethernet_frame(kSrc, kDst, 6699, 7788, payload_of(100));
  EXPECT_FALSE(parse_udp_datagram(kLinkUser0, eth));
  auto f = eth;
  f[12] = 0x86;  // IPv6 EtherType
  f[13] = 0xDD;
  EXPECT_FALSE(parse_udp_datagram(kLinkEthernet, f));
  f = eth;
  f[14] = 0x65;  // IP version 6 in the header
  EXPECT_FALSE(parse_udp_datagram(kLinkEthernet, f));
  f = eth;
  f[14] = 0x44;  // header length 16 bytes
  EXPECT_FALSE(parse_udp_datagram(kLinkEthernet, f));
  f = eth;
  f[14 + 9] = 6;  // TCP
  EXPECT_FALSE(parse_udp_datagram(kLinkEthernet, f));
  f = eth;
  f[14 + 6] = 0x20;  // more fragments
  EXPECT_FALSE(parse_udp_datagram(kLinkEthernet, f));
  f = eth;
  f[14 + 7] = 0x10;  // fragment offset
  EXPECT_FALSE(parse_udp_datagram(kLinkEthernet, f));
  f = eth;
  f[14 + 20 + 5] = 4;  // UDP length below its own header
  f[14 + 20 + 4] = 0;
  EXPECT_FALSE(parse_udp_datagram(kLinkEthernet, f));
  // Cut anywhere inside the headers: nothing; inside the payload: what is there.
  for (std::size_t n = 0; n <= eth.size(); ++n) {
    const auto d = parse_udp_datagram(kLinkEthernet, std::span(eth).first(n));
    if (n < 14 + 20 + 8) {
      EXPECT_FALSE(d) << n;
    } else {
      ASSERT_TRUE(d) << n;
      EXPECT_EQ(d->payload.size(), n - 42);
    }
  }
}

TEST(UdpFrame, IgnoresLinkPaddingAfterTheDatagram) {
  auto eth = make_udp_ethernet_frame(kSrc, kDst, 6699, 7788, payload_of(4));
  eth.resize(60, 0xEE);  // Ethernet minimum frame
  const auto d = parse_udp_datagram(kLinkEthernet, eth);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->payload.size(), 4u);
}

TEST(UdpFrame, BuildsAValidIpv4Header) {
  const auto f = make_udp_ethernet_frame(kSrc, kDst, 1, 2, payload_of(10));
  ASSERT_EQ(f.size(), 14u + 20 + 8 + 10);
  std::uint32_t sum = 0;
  for (std::size_t i = 14; i < 34; i += 2) sum += (f[i] << 8) | f[i + 1];
  while (sum > 0xFFFF) sum = (sum & 0xFFFF) + (sum >> 16);
  EXPECT_EQ(sum, 0xFFFFu);
  EXPECT_EQ((f[16] << 8) | f[17], 20 + 8 + 10);
  EXPECT_EQ((f[38] << 8) | f[39], 8 + 10);
  EXPECT_THROW(make_udp_ethernet_frame(kSrc, kDst, 1, 2, std::vector<std::uint8_t>(70000)), std::invalid_argument);
}

TEST(UdpFrame, RebuildsTheFixtureFramesFromTheEtherTypeOn) {
  TUMBLE_REQUIRE_FIXTURE("rs16/rs16_synthetic.pcap");
  Reader reader(tumble::test::fixture_path("rs16/rs16_synthetic.pcap").string());
  ASSERT_EQ(reader.link_type(), kLinkEthernet);
  int frames = 0;
  while (const auto r = reader.next()) {
    const auto d = parse_udp_datagram(reader.link_type(), r->bytes);
    ASSERT_TRUE(d);
    const auto& b = r->bytes;
    const std::uint32_t dst = (std::uint32_t{b[30]} << 24) | (b[31] << 16) | (b[32] << 8) | b[33];
    const auto again = make_udp_ethernet_frame(d->src_ip, dst, d->src_port, d->dst_port, d->payload);
    ASSERT_EQ(again.size(), b.size());
    // The MAC addresses are the capture's own; everything after them is rebuilt exactly.
    EXPECT_TRUE(std::equal(again.begin() + 12, again.end(), b.begin() + 12)) << "frame " << frames;
    ++frames;
  }
  EXPECT_GT(frames, 0);
}

}  // namespace
}  // namespace tumble::pcap
