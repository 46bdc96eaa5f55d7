// Order statistics for the result tables and the box plot.
//
// Quantiles are Hyndman & Fan type 7 (the default of R, NumPy and
// matplotlib's boxplot): the p-quantile of n sorted values x₀..x_{n-1} is
// interpolated linearly at position h = (n − 1)·p. So Q1/median/Q3 of
// {1, 2, 3, 4} are 1.75 / 2.5 / 3.25.
// Whiskers are Tukey's (as matplotlib draws the paper's kind of figure): the
// most extreme values within 1.5 IQR of the box; values beyond are outliers.
#pragma once

#include <cstddef>
#include <vector>

namespace tumble::eval {

// sorted: ascending, non-empty; p in [0, 1].
double quantile_sorted(const std::vector<double>& sorted, double p);

struct BoxStats {
  std::size_t count = 0;
  double min = 0.0;
  double q1 = 0.0;
  double median = 0.0;
  double q3 = 0.0;
  double max = 0.0;
  double whisker_low = 0.0;
  double whisker_high = 0.0;
  std::vector<double> outliers;  // ascending
};

// values: finite, non-empty (throws std::invalid_argument otherwise).
BoxStats box_stats(std::vector<double> values);

}  // namespace tumble::eval
