#include "tools/view/lcm_url.hpp"

#include <gtest/gtest.h>

namespace tumble::view {
namespace {

TEST(LcmUrl, AUdpmUrlWithoutAReceiveBufferGetsOne) {
  EXPECT_EQ(with_receive_buffer("udpm://239.255.76.67:7667?ttl=0"),
            "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304");
  EXPECT_EQ(with_receive_buffer("udpm://239.255.76.67:7667"), "udpm://239.255.76.67:7667?recv_buf_size=4194304");
}

TEST(LcmUrl, AnExplicitReceiveBufferAndOtherProvidersAreLeftAlone) {
  EXPECT_EQ(with_receive_buffer("udpm://239.255.76.67:7667?ttl=1&recv_buf_size=1000"),
            "udpm://239.255.76.67:7667?ttl=1&recv_buf_size=1000");
  EXPECT_EQ(with_receive_buffer("memq://"), "memq://");
  EXPECT_EQ(with_receive_buffer("file:///tmp/run.lcmlog?mode=r"), "file:///tmp/run.lcmlog?mode=r");
}

}  // namespace
}  // namespace tumble::view
