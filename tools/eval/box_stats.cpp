#include "tools/eval/box_stats.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tumble::eval {

double quantile_sorted(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) throw std::invalid_argument("quantile of no values");
  if (!(p >= 0.0 && p <= 1.0)) throw std::invalid_argument("quantile probability outside [0, 1]");
  const double h = static_cast<double>(sorted.size() - 1) * p;
  const auto below = static_cast<std::size_t>(std::floor(h));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (h - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

BoxStats box_stats(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("box statistics of no values");
  if (!std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); }))
    throw std::invalid_argument("box statistics of a non-finite value");
  std::sort(values.begin(), values.end());
  BoxStats stats;
  stats.count = values.size();
  stats.min = values.front();
  stats.max = values.back();
  stats.q1 = quantile_sorted(values, 0.25);
  stats.median = quantile_sorted(values, 0.5);
  stats.q3 = quantile_sorted(values, 0.75);
  const double reach = 1.5 * (stats.q3 - stats.q1);
  const double low_fence = stats.q1 - reach;
  const double high_fence = stats.q3 + reach;
  stats.whisker_low = *std::find_if(values.begin(), values.end(), [&](double v) { return v >= low_fence; });
  stats.whisker_high = *std::find_if(values.rbegin(), values.rend(), [&](double v) { return v <= high_fence; });
  for (const double v : values)
    if (v < low_fence || v > high_fence) stats.outliers.push_back(v);
  return stats;
}

}  // namespace tumble::eval
