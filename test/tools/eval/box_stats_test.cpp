#include "tools/eval/box_stats.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

namespace tumble::eval {
namespace {

TEST(BoxStats, QuartilesInterpolateBetweenOrderStatistics) {
  // Type 7: h = (n - 1) p.
  const BoxStats four = box_stats({4.0, 1.0, 3.0, 2.0});
  EXPECT_DOUBLE_EQ(four.q1, 1.75);
  EXPECT_DOUBLE_EQ(four.median, 2.5);
  EXPECT_DOUBLE_EQ(four.q3, 3.25);
  const BoxStats five = box_stats({5.0, 1.0, 4.0, 2.0, 3.0});
  EXPECT_DOUBLE_EQ(five.q1, 2.0);
  EXPECT_DOUBLE_EQ(five.median, 3.0);
  EXPECT_DOUBLE_EQ(five.q3, 4.0);
  EXPECT_DOUBLE_EQ(five.min, 1.0);
  EXPECT_DOUBLE_EQ(five.max, 5.0);
  EXPECT_EQ(five.count, 5u);
  const BoxStats one = box_stats({7.0});
  EXPECT_DOUBLE_EQ(one.q1, 7.0);
  EXPECT_DOUBLE_EQ(one.q3, 7.0);
  EXPECT_DOUBLE_EQ(quantile_sorted({10.0, 20.0}, 0.99), 19.9);
}

TEST(BoxStats, WhiskersStopAtTheLastValueWithinOneAndAHalfIqr) {
  // Q1 = 2.5, Q3 = 7.5 (n = 11 values 0..9 and 30): IQR 5, fences -5 and 15.
  const BoxStats stats = box_stats({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 30});
  EXPECT_DOUBLE_EQ(stats.q1, 2.5);
  EXPECT_DOUBLE_EQ(stats.q3, 7.5);
  EXPECT_DOUBLE_EQ(stats.whisker_low, 0.0);
  EXPECT_DOUBLE_EQ(stats.whisker_high, 9.0);
  ASSERT_EQ(stats.outliers.size(), 1u);
  EXPECT_DOUBLE_EQ(stats.outliers[0], 30.0);
  EXPECT_DOUBLE_EQ(stats.max, 30.0);
}

TEST(BoxStats, LowOutliersToo) {
  const BoxStats stats = box_stats({-20, 10, 11, 12, 13, 14});
  EXPECT_DOUBLE_EQ(stats.whisker_low, 10.0);
  EXPECT_DOUBLE_EQ(stats.whisker_high, 14.0);
  ASSERT_EQ(stats.outliers.size(), 1u);
  EXPECT_DOUBLE_EQ(stats.outliers[0], -20.0);
}

TEST(BoxStats, RefusesNoValuesAndNonFiniteOnes) {
  EXPECT_THROW(box_stats({}), std::invalid_argument);
  EXPECT_THROW(box_stats({1.0, std::numeric_limits<double>::quiet_NaN()}), std::invalid_argument);
  EXPECT_THROW(quantile_sorted({1.0}, 1.5), std::invalid_argument);
}

}  // namespace
}  // namespace tumble::eval
