// Median, min and max of the values seen during one status period, in fixed
// storage: the median is over the newest N values, min and max over all of
// them. No allocation, ever.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace tumble::daemon {

template <std::size_t N>
class PeriodStats {
 public:
  void add(float value) {
    values_[added_ % N] = value;
    min_ = added_ == 0 ? value : std::min(min_, value);
    max_ = added_ == 0 ? value : std::max(max_, value);
    ++added_;
  }

  std::uint64_t count() const { return added_; }
  float min() const { return added_ ? min_ : kNone; }
  float max() const { return added_ ? max_ : kNone; }

  // Of the newest min(count(), N) values; NaN when there are none.
  float median() const {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(added_, N));
    if (n == 0) return kNone;
    std::array<float, N> sorted = values_;
    const auto begin = sorted.begin();
    std::nth_element(begin, begin + n / 2, begin + n);
    const float upper = sorted[n / 2];
    if (n % 2 == 1) return upper;
    const float lower = *std::max_element(begin, begin + n / 2);
    return 0.5f * (lower + upper);
  }

  void reset() { added_ = 0; }

 private:
  static constexpr float kNone = std::numeric_limits<float>::quiet_NaN();
  std::array<float, N> values_{};
  std::uint64_t added_ = 0;
  float min_ = 0.0f;
  float max_ = 0.0f;
};

}  // namespace tumble::daemon
