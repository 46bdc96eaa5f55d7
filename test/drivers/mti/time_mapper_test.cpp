#include "drivers/mti/time_mapper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace tumble::mti {
namespace {

constexpr double kHostStart_s = 1.7e9;

// Serial and scheduling delay: never below the floor, mostly small, sometimes
// several ms. Built from raw mt19937 output so every platform draws the same.
class Delays {
 public:
  double next_s() {
    const double u = static_cast<double>(gen_()) / 4294967296.0;
    return 0.002 + 0.004 * u * u * u;
  }

 private:
  std::mt19937 gen_{12345};
};

TEST(TimeMapper, ConstantLatencyGivesTheFirstOffset) {
  TimeMapper m;
  EXPECT_FALSE(m.ready());
  for (int i = 0; i < 500; ++i) m.observe(100.0 + i * 0.01, kHostStart_s + i * 0.01 + 0.003);
  ASSERT_TRUE(m.ready());
  EXPECT_NEAR(m.host_time(103.0), kHostStart_s + 3.003, 1e-6);
  EXPECT_NEAR(m.offset_s(), kHostStart_s + 0.003 - 100.0, 1e-6);
  EXPECT_EQ(m.drift(), 0.0);
  EXPECT_NEAR(m.jitter_s(), 0.0, 1e-6);
}

TEST(TimeMapper, FollowsTheLowerEnvelopeAndItsDrift) {
  const double drift = 20e-6;
  TimeMapper m;
  Delays delays;
  double worst_after_warmup_s = 0;
  for (int i = 0; i < 100 * 120; ++i) {
    const double sensor_s = 5000.0 + i * 0.01;
    const double floor_s = kHostStart_s + (sensor_s - 5000.0) * (1 + drift) + 0.002;
    m.observe(sensor_s, floor_s + delays.next_s() - 0.002);
    if (i > 100 * 30) worst_after_warmup_s = std::max(worst_after_warmup_s, std::abs(m.host_time(sensor_s) - floor_s));
  }
  EXPECT_NEAR(m.drift(), drift, 3e-6);
  EXPECT_LT(worst_after_warmup_s, 1e-4);  // the jitter is up to 4 ms
  EXPECT_GT(m.jitter_s(), 2e-4);
}

TEST(TimeMapper, NoDriftBeforeTheSpanCanShowIt) {
  TimeMapper m;
  for (int i = 0; i < 500; ++i) m.observe(i * 0.01, kHostStart_s + i * 0.01 * (1 + 100e-6));
  EXPECT_EQ(m.drift(), 0.0);  // 5 s < min_drift_span_s
  for (int i = 500; i < 2000; ++i) m.observe(i * 0.01, kHostStart_s + i * 0.01 * (1 + 100e-6));
  EXPECT_NEAR(m.drift(), 100e-6, 1e-7);
}

TEST(TimeMapper, AnImpossibleDriftIsClamped) {
  TimeMapperOptions options;
  options.max_abs_drift = 50e-6;
  TimeMapper m(options);
  for (int i = 0; i < 3000; ++i) m.observe(i * 0.01, kHostStart_s + i * 0.01 * (1 + 1e-3));
  EXPECT_EQ(m.drift(), 50e-6);
  // Clamped, the line still stays under every observation.
  EXPECT_LE(m.host_time(29.99), kHostStart_s + 29.99 * (1 + 1e-3) + 1e-9);
}

TEST(TimeMapper, ResetStartsAfresh) {
  TimeMapper m;
  for (int i = 0; i < 100; ++i) m.observe(i * 0.01, kHostStart_s + i * 0.01);
  m.reset();
  EXPECT_FALSE(m.ready());
  m.observe(7.0, kHostStart_s + 100.0);
  EXPECT_NEAR(m.host_time(8.0), kHostStart_s + 101.0, 1e-6);
}

TEST(TimeMapper, BadOptionsAreRefused) {
  TimeMapperOptions options;
  options.bucket_s = 0;
  EXPECT_THROW(TimeMapper{options}, std::invalid_argument);
}

}  // namespace
}  // namespace tumble::mti
