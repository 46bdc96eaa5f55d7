#include "drivers/pcap/pcap_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <vector>

namespace tumble::pcap {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("tumble_pcap_test_" + name)).string();
}

TEST(PcapFile, WriteThenReadKeepsBytesAndNanosecondTimes) {
  const auto path = temp_path("roundtrip.pcap");
  const std::vector<std::uint8_t> a{1, 2, 3}, b{0xFA, 0xFF, 0x36};
  {
    Writer w(path, kLinkUser0);
    w.write(1'700'000'000'123'456'789, a);
    w.write(1'700'000'000'987'654'321, b);
  }
  Reader r(path);
  EXPECT_EQ(r.link_type(), kLinkUser0);
  auto first = r.next();
  ASSERT_TRUE(first);
  EXPECT_EQ(first->t_ns, 1'700'000'000'123'456'789);
  EXPECT_EQ(std::vector<std::uint8_t>(first->bytes.begin(), first->bytes.end()), a);
  auto second = r.next();
  ASSERT_TRUE(second);
  EXPECT_EQ(second->t_ns, 1'700'000'000'987'654'321);
  EXPECT_EQ(std::vector<std::uint8_t>(second->bytes.begin(), second->bytes.end()), b);
  EXPECT_FALSE(r.next());
  EXPECT_FALSE(r.truncated());
  std::filesystem::remove(path);
}

TEST(PcapFile, MissingFileThrowsWithItsName) {
  try {
    Reader r("/nonexistent/tumble.pcap");
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/tumble.pcap"), std::string::npos);
  }
}

TEST(PcapFile, NotAPcapThrows) {
  const auto path = temp_path("garbage.pcap");
  std::ofstream(path) << "this is not a capture file at all";
  EXPECT_THROW(Reader r(path), Error);
  std::filesystem::remove(path);
}

TEST(PcapFile, TruncatedRecordEndsTheStreamAndSaysSo) {
  const auto path = temp_path("truncated.pcap");
  {
    Writer w(path, kLinkEthernet);
    w.write(1'000'000'000, std::vector<std::uint8_t>(100, 7));
    w.write(2'000'000'000, std::vector<std::uint8_t>(100, 8));
  }
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 50);
  Reader r(path);
  ASSERT_TRUE(r.next());
  EXPECT_FALSE(r.next());
  EXPECT_TRUE(r.truncated());
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace tumble::pcap
