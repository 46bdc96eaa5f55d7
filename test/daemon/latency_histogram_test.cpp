#include "daemon/latency_histogram.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace tumble::daemon {
namespace {

TEST(LatencyHistogram, EmptyHasNoPercentileOrMaximum) {
  const LatencyHistogram h;
  EXPECT_EQ(h.count(), 0u);
  EXPECT_TRUE(std::isnan(h.percentile_ms(0.5)));
  EXPECT_TRUE(std::isnan(h.max_ms()));
}

TEST(LatencyHistogram, PercentilesAreWithinOneBinAboveTheTrueValue) {
  LatencyHistogram h;
  // 1..1000 µs: the true p50 is 0.5 ms, the true p99 0.99 ms.
  for (int us = 1; us <= 1000; ++us) h.add(us * 1e-3);
  EXPECT_EQ(h.count(), 1000u);
  const double bin = std::pow(10.0, 1.0 / 20);  // +12 %
  EXPECT_GE(h.percentile_ms(0.5), 0.5);
  EXPECT_LE(h.percentile_ms(0.5), 0.5 * bin);
  EXPECT_GE(h.percentile_ms(0.99), 0.99);
  EXPECT_LE(h.percentile_ms(0.99), 0.99 * bin);
  EXPECT_DOUBLE_EQ(h.max_ms(), 1.0);
  EXPECT_DOUBLE_EQ(h.percentile_ms(1.0), 1.0);  // capped at the exact maximum
}

TEST(LatencyHistogram, ARareOutlierMovesTheMaximumNotTheP99) {
  LatencyHistogram h;
  for (int i = 0; i < 999; ++i) h.add(0.04);
  h.add(4.0);
  EXPECT_LT(h.percentile_ms(0.99), 0.05);
  EXPECT_DOUBLE_EQ(h.max_ms(), 4.0);
}

TEST(LatencyHistogram, ExtremesLandInTheEndBinsAndNegativeOrNanIsIgnored) {
  LatencyHistogram h;
  h.add(0.0);
  h.add(1e6);  // 1000 s
  h.add(-1.0);
  h.add(std::nan(""));
  EXPECT_EQ(h.count(), 2u);
  EXPECT_LE(h.percentile_ms(0.5), 1e-3);
  EXPECT_DOUBLE_EQ(h.max_ms(), 1e6);
  h.reset();
  EXPECT_EQ(h.count(), 0u);
}

}  // namespace
}  // namespace tumble::daemon
