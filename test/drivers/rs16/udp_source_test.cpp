// The live source on loopback only: datagrams are sent to 127.0.0.1 before the
// io_context runs, and run_for's limit is only a guard; the handler stops the
// context as soon as the expected datagrams are in.
#include "drivers/rs16/udp_source.hpp"

#include <gtest/gtest.h>

#include <boost/asio/ip/udp.hpp>
#include <chrono>
#include <fstream>
#include <vector>

#include "drivers/rs16/difop_encode.hpp"
#include "drivers/rs16/msop_encode.hpp"
#include "test/drivers/rs16/packet_stream.hpp"

namespace tumble::rs16 {
namespace {

using boost::asio::ip::udp;

constexpr auto kGuard = std::chrono::seconds(20);

struct Received {
  PacketKind kind;
  double arrival_s;
  std::uint32_t source_ip;
  std::vector<std::uint8_t> payload;
};

UdpSourceConfig loopback_any_port() {
  UdpSourceConfig c;
  c.bind_address = "127.0.0.1";
  c.ports.msop_port = 0;
  c.ports.difop_port = 0;
  return c;
}

void send_from(boost::asio::io_context& io, const char* from, std::uint16_t to_port,
               std::span<const std::uint8_t> payload) {
  udp::socket s(io, udp::endpoint(boost::asio::ip::make_address_v4(from), 0));
  s.send_to(boost::asio::buffer(payload.data(), payload.size()),
            udp::endpoint(boost::asio::ip::make_address_v4("127.0.0.1"), to_port));
}

TEST(Rs16UdpSource, ReceivesBothPortsWithArrivalTimes) {
  boost::asio::io_context io;
  std::vector<Received> got;
  const std::size_t expected = 4;
  UdpSource source(io, loopback_any_port(), [&](const LidarDatagram& d) {
    got.push_back({d.kind, d.arrival_s, d.source_ip, {d.payload.begin(), d.payload.end()}});
    if (got.size() == expected) io.stop();
  });
  ASSERT_NE(source.msop_port(), source.difop_port());
  const auto before_s = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  const auto msop = encode_msop(test::stream_packet({}, 0));
  const auto difop = encode_difop(DifopData{});
  for (int i = 0; i < 3; ++i) send_from(io, "127.0.0.1", source.msop_port(), msop);
  send_from(io, "127.0.0.1", source.difop_port(), difop);
  source.start();
  io.run_for(kGuard);
  ASSERT_EQ(got.size(), expected);
  int msop_seen = 0;
  for (const Received& r : got) {
    EXPECT_EQ(r.source_ip, 0x7F000001u);
    EXPECT_GE(r.arrival_s, before_s - 1.0);  // CLOCK_REALTIME, stamped on receipt
    if (r.kind == PacketKind::Msop) {
      ++msop_seen;
      EXPECT_TRUE(std::equal(msop.begin(), msop.end(), r.payload.begin(), r.payload.end()));
    } else {
      EXPECT_TRUE(std::equal(difop.begin(), difop.end(), r.payload.begin(), r.payload.end()));
    }
  }
  EXPECT_EQ(msop_seen, 3);
  EXPECT_EQ(source.stats().msop, 3u);
  EXPECT_EQ(source.stats().difop, 1u);
}

TEST(Rs16UdpSource, DropsOtherSendersAndOversizeDatagrams) {
  boost::asio::io_context io;
  UdpSourceConfig config = loopback_any_port();
  config.ports.source_ip = 0x7F000001;  // 127.0.0.1 only
  std::vector<Received> got;
  UdpSource source(io, config, [&](const LidarDatagram& d) {
    got.push_back({d.kind, d.arrival_s, d.source_ip, {d.payload.begin(), d.payload.end()}});
    io.stop();  // the accepted one is sent last
  });
  const auto msop = encode_msop(test::stream_packet({}, 0));
  send_from(io, "127.0.0.2", source.msop_port(), msop);  // another sender (still loopback)
  send_from(io, "127.0.0.1", source.msop_port(), std::vector<std::uint8_t>(4000, 0xAB));
  send_from(io, "127.0.0.1", source.msop_port(), msop);
  source.start();
  io.run_for(kGuard);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].source_ip, 0x7F000001u);
  EXPECT_EQ(source.stats().wrong_source, 1u);
  EXPECT_EQ(source.stats().oversize, 1u);
  EXPECT_EQ(source.stats().msop, 1u);
}

TEST(Rs16UdpSource, StopEndsReceiving) {
  boost::asio::io_context io;
  int calls = 0;
  UdpSource source(io, loopback_any_port(), [&](const LidarDatagram&) {
    ++calls;
    // io keeps running; stop() alone must leave nothing armed
  });
  source.start();
  source.stop();
  send_from(io, "127.0.0.1", source.msop_port(), encode_msop(test::stream_packet({}, 0)));
  // With nothing armed the context runs out of work and returns at once.
  io.run_for(kGuard);
  EXPECT_EQ(calls, 0);
}

TEST(Rs16UdpSource, BindFailureNamesTheAddress) {
  boost::asio::io_context io;
  UdpSourceConfig config = loopback_any_port();
  UdpSource first(io, config, [](const LidarDatagram&) {});
  config.ports.msop_port = first.msop_port();  // already taken
  try {
    UdpSource second(io, config, [](const LidarDatagram&) {});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("127.0.0.1:" + std::to_string(first.msop_port())), std::string::npos)
        << e.what();
  }
  config = loopback_any_port();
  config.bind_address = "not-an-address";
  EXPECT_THROW(UdpSource(io, config, [](const LidarDatagram&) {}), std::runtime_error);
}

int rmem_max_bytes() {
  std::ifstream in("/proc/sys/net/core/rmem_max");
  int bytes = 0;
  in >> bytes;
  return bytes;
}

// The kernel caps SO_RCVBUF at net.core.rmem_max without an error: the
// source reads back what it got.
TEST(Rs16UdpSource, ReadsBackTheReceiveBufferTheKernelGranted) {
  const int cap = rmem_max_bytes();
  if (cap <= 0 || cap > (1 << 29)) GTEST_SKIP() << "net.core.rmem_max unreadable or too large to exceed";
  boost::asio::io_context io;
  UdpSourceConfig config = loopback_any_port();
  config.receive_buffer_bytes = cap / 2;
  EXPECT_EQ(UdpSource(io, config, [](const LidarDatagram&) {}).granted_receive_buffer_bytes(), cap / 2);
  config.receive_buffer_bytes = 2 * cap;
  EXPECT_EQ(UdpSource(io, config, [](const LidarDatagram&) {}).granted_receive_buffer_bytes(), cap);
}

}  // namespace
}  // namespace tumble::rs16
