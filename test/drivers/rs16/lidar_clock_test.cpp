#include "drivers/rs16/lidar_clock.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace tumble::rs16 {
namespace {

constexpr double kPacket_s = 1332e-6;

// A lidar clock that is offset and drifts against the host, and arrivals
// delayed by a fixed latency plus random jitter (a few packets are fast).
struct Link {
  double offset_s = 1.5e8;      // host - lidar at lidar time 0
  double drift = 30e-6;         // host gains 30 us per lidar second
  double latency_s = 120e-6;
  std::mt19937 rng{7};
  std::exponential_distribution<double> jitter{1.0 / 300e-6};

  double host_of(double lidar_s) const { return lidar_s + offset_s + drift * lidar_s; }
  double arrival_of(double lidar_s) { return host_of(lidar_s) + kPacket_s + latency_s + jitter(rng); }
};

TEST(Rs16LidarClock, RecoversOffsetAndDriftFromTheLowerEnvelope) {
  Link link;
  LidarClockMapper mapper;
  double worst_late_s = 0.0;
  for (int i = 0; i < 12 * 751; ++i) {
    const double lidar_s = 1000.0 + i * kPacket_s;
    const double host_s = mapper.observe(lidar_s, link.arrival_of(lidar_s), kPacket_s);
    const double error_s = host_s - (link.host_of(lidar_s) + link.latency_s);
    if (i > 3 * 751) worst_late_s = std::max(worst_late_s, std::abs(error_s));
  }
  // After a few windows the map sits on the fastest packets, not on the jitter.
  EXPECT_LT(worst_late_s, 10e-6);
  EXPECT_NEAR(mapper.drift(), link.drift, 2e-6);
  EXPECT_GT(mapper.jitter_s(), 100e-6);  // mean jitter is 300 us
  EXPECT_EQ(mapper.resets(), 0u);
  EXPECT_EQ(mapper.envelope_points(), 8u);
  const double later_s = 1000.0 + 12 * 751 * kPacket_s;
  EXPECT_NEAR(mapper.to_host(later_s), link.host_of(later_s) + link.latency_s, 10e-6);
}

TEST(Rs16LidarClock, StartsOnTheFirstPacket) {
  LidarClockMapper mapper;
  EXPECT_FALSE(mapper.started());
  EXPECT_DOUBLE_EQ(mapper.observe(10.0, 110.0 + kPacket_s, kPacket_s), 110.0);
  EXPECT_TRUE(mapper.started());
  // A faster packet lowers the envelope at once.
  EXPECT_DOUBLE_EQ(mapper.observe(10.1, 110.1 - 0.001 + kPacket_s, kPacket_s), 110.1 - 0.001);
  EXPECT_NEAR(mapper.offset_s(), 99.999, 1e-9);
}

TEST(Rs16LidarClock, FollowsASteppedSensorClock) {
  Link link;
  link.drift = 0.0;
  LidarClockMapper mapper;
  double lidar_s = 0.0;
  for (int i = 0; i < 3000; ++i, lidar_s += kPacket_s) mapper.observe(lidar_s, link.arrival_of(lidar_s), kPacket_s);
  // The lidar's clock is set back by an hour (e.g. it got a PTP fix): same host times.
  link.offset_s += 3600.0;
  lidar_s -= 3600.0;
  double error_s = 0.0;
  for (int i = 0; i < 3000; ++i, lidar_s += kPacket_s)
    error_s = mapper.observe(lidar_s, link.arrival_of(lidar_s), kPacket_s) - (link.host_of(lidar_s) + link.latency_s);
  EXPECT_GE(mapper.resets(), 1u);
  EXPECT_LT(std::abs(error_s), 20e-6);

  // And forward by ten seconds: the packets seem to arrive far too early.
  link.offset_s -= 10.0;
  const auto resets_before = mapper.resets();
  for (int i = 0; i < 3000; ++i, lidar_s += kPacket_s)
    error_s = mapper.observe(lidar_s + 10.0, link.arrival_of(lidar_s + 10.0), kPacket_s) -
              (link.host_of(lidar_s + 10.0) + link.latency_s);
  EXPECT_GT(mapper.resets(), resets_before);
  EXPECT_LT(std::abs(error_s), 20e-6);

  // The host clock steps forward by 5 s: every packet now seems 5 s late, which
  // only a whole window of them proves.
  link.offset_s += 5.0;
  const auto resets_before_host_step = mapper.resets();
  for (int i = 0; i < 3000; ++i, lidar_s += kPacket_s)
    error_s = mapper.observe(lidar_s + 10.0, link.arrival_of(lidar_s + 10.0), kPacket_s) -
              (link.host_of(lidar_s + 10.0) + link.latency_s);
  EXPECT_GT(mapper.resets(), resets_before_host_step);
  EXPECT_LT(std::abs(error_s), 20e-6);
}

TEST(Rs16LidarClock, RefusesConfigOutOfRange) {
  EXPECT_THROW(LidarClockMapper({0.0, 8, 0.5}), std::invalid_argument);
  EXPECT_THROW(LidarClockMapper({1.0, 1, 0.5}), std::invalid_argument);
  EXPECT_THROW(LidarClockMapper({1.0, 33, 0.5}), std::invalid_argument);
  EXPECT_THROW(LidarClockMapper({1.0, 8, -1.0}), std::invalid_argument);
}

}  // namespace
}  // namespace tumble::rs16
