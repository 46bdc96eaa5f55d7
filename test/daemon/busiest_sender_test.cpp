// Without lidar.source_ip the lidar is the busiest sender on its ports.
#include "daemon/busiest_sender.hpp"

#include <gtest/gtest.h>

namespace tumble::daemon {
namespace {

TEST(BusiestSender, AnOccasionalOtherSenderIsNeverTheLidar) {
  BusiestSender s;
  double t = 0.0;
  for (int i = 0; i < 5000; ++i, t += 0.0013) EXPECT_EQ(s.observe(i % 20 == 19 ? 2 : 1, t), i % 20 != 19) << i;
  EXPECT_EQ(s.lidar(), 1u);
}

TEST(BusiestSender, FollowsALidarReplacedByAnotherAddressWithinTwoWindows) {
  BusiestSender s;
  const std::uint32_t a = 1, b = 2;
  double t = 0.0;
  for (int i = 0; i < 1000; ++i, t += 0.001) EXPECT_TRUE(s.observe(a, t));
  EXPECT_FALSE(s.observe(b, t));
  for (int i = 0; i < 2000 && !s.observe(b, t); ++i) t += 0.001;
  EXPECT_EQ(s.lidar(), b);
  EXPECT_LT(t, 1.0 + 2 * BusiestSender::kWindow_s);
  EXPECT_TRUE(s.changed());
}

}  // namespace
}  // namespace tumble::daemon
