// The lidar is who the configuration says, or the first sender, for the
// whole run; a second host's rate is measured to report it.
#include "daemon/lidar_identity.hpp"

#include <gtest/gtest.h>

#include "daemon/datagram_rate.hpp"

namespace tumble::daemon {
namespace {

TEST(LidarIdentity, AConfiguredAddressIsTheLidarFromTheStart) {
  LidarIdentity identity(7u);
  EXPECT_TRUE(identity.may_be_lidar(7));
  EXPECT_FALSE(identity.may_be_lidar(8));
  EXPECT_FALSE(identity.lock_on(8));
  EXPECT_EQ(identity.lidar(), 7u);
}

TEST(LidarIdentity, WithoutOneTheFirstSenderIsTheLidarAndStaysIt) {
  LidarIdentity identity(std::nullopt);
  EXPECT_TRUE(identity.may_be_lidar(8));
  EXPECT_TRUE(identity.lock_on(7));
  EXPECT_FALSE(identity.lock_on(8));
  EXPECT_FALSE(identity.may_be_lidar(8));
  EXPECT_EQ(identity.lidar(), 7u);
}

TEST(DatagramRate, CountsWholeWindowsOfArrivalTimeAndFallsToZeroInSilence) {
  DatagramRate rate;
  double t_s = 100.0;
  for (int i = 0; i < 1125; ++i, t_s += 1.0 / 1125.0) {  // 1.5x an RS-16's 750 packets/s
    rate.advance(t_s);
    rate.count();
  }
  rate.advance(t_s);
  EXPECT_NEAR(rate.rate_hz(), 1125.0, 1.0);
  rate.advance(t_s + 0.5);  // the lidar's own datagrams close windows
  EXPECT_NEAR(rate.rate_hz(), 1125.0, 1.0);
  rate.advance(t_s + 1.2);
  EXPECT_EQ(rate.rate_hz(), 0.0);
  rate.count();
  rate.advance(t_s + 5.0);  // seconds without a datagram at all
  EXPECT_EQ(rate.rate_hz(), 0.0);
}

}  // namespace
}  // namespace tumble::daemon
