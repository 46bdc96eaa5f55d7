#include "tools/view/listen_address.hpp"

#include <gtest/gtest.h>

namespace tumble::view {
namespace {

TEST(ListenAddress, ReadsIpv4AndBracketedIpv6WithTheirPort) {
  const auto v4 = parse_listen_address("127.0.0.1:8076");
  ASSERT_TRUE(v4);
  EXPECT_EQ(v4->address().to_string(), "127.0.0.1");
  EXPECT_EQ(v4->port(), 8076);
  const auto v6 = parse_listen_address("[::1]:0");
  ASSERT_TRUE(v6);
  EXPECT_TRUE(v6->address().is_v6());
  EXPECT_EQ(v6->port(), 0);
}

TEST(ListenAddress, RejectsWhatIsNotAnAddressAndAPort) {
  for (const char* bad : {"", "8076", ":8076", "127.0.0.1", "127.0.0.1:", "127.0.0.1:65536", "127.0.0.1:80x",
                          "localhost:8076", "[::1:8076", "::1:8076"})
    EXPECT_FALSE(parse_listen_address(bad)) << bad;
}

}  // namespace
}  // namespace tumble::view
