#include "tools/calib/speed_bins.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tumble::calib {
namespace {

double quantile_sorted(const std::vector<double>& sorted, double q) {
  const double position = q * static_cast<double>(sorted.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  const double a = position - static_cast<double>(below);
  return (1 - a) * sorted[below] + a * sorted[above];
}

}  // namespace

Quartiles quartiles(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("quartiles of an empty set");
  std::sort(values.begin(), values.end());
  return Quartiles{quantile_sorted(values, 0.25), quantile_sorted(values, 0.5), quantile_sorted(values, 0.75)};
}

double median(std::vector<double> values) { return quartiles(std::move(values)).median; }

std::vector<double> bin_centres(std::span<const double> nominal_speeds) {
  std::vector<double> centres{0.0};
  for (const double s : nominal_speeds) centres.push_back(std::abs(s));
  std::sort(centres.begin(), centres.end());
  centres.erase(std::unique(centres.begin(), centres.end()), centres.end());
  return centres;
}

std::size_t bin_of(std::span<const double> centres, double speed) {
  if (centres.empty()) throw std::invalid_argument("bin_of: no bins");
  const double s = std::abs(speed);
  std::size_t best = 0;
  for (std::size_t i = 1; i < centres.size(); ++i)
    if (std::abs(centres[i] - s) < std::abs(centres[best] - s)) best = i;
  return best;
}

}  // namespace tumble::calib
