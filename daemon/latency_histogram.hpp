// Latencies counted in log-spaced bins (20 per decade, 1 µs to 10 s): any
// percentile of any number of values in fixed storage, to within one bin
// (+12 %), with no allocation. The maximum is exact.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace tumble::daemon {

class LatencyHistogram {
 public:
  void add(double ms) {
    if (!(ms >= 0)) return;  // NaN or a clock that went backwards: not a latency
    ++bins_[bin_of(ms)];
    ++count_;
    max_ms_ = std::max(max_ms_, ms);
  }

  std::uint64_t count() const { return count_; }
  double max_ms() const { return count_ ? max_ms_ : kNone; }

  // The upper edge of the bin holding the p-quantile (p in [0, 1]), capped
  // at the maximum; NaN when empty.
  double percentile_ms(double p) const {
    if (count_ == 0) return kNone;
    const auto rank = static_cast<std::uint64_t>(std::ceil(std::clamp(p, 0.0, 1.0) * static_cast<double>(count_)));
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < kBins; ++i) {
      seen += bins_[i];
      if (seen >= std::max<std::uint64_t>(rank, 1)) return std::min(upper_edge_ms(i), max_ms_);
    }
    return max_ms_;
  }

  void reset() { *this = LatencyHistogram{}; }

 private:
  static constexpr double kFirstEdgeMs = 1e-3;
  static constexpr int kBinsPerDecade = 20;
  static constexpr std::size_t kBins = 7 * kBinsPerDecade;  // the last bin takes everything above 10 s
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

  static std::size_t bin_of(double ms) {
    if (ms < kFirstEdgeMs) return 0;
    const double bin = std::floor(kBinsPerDecade * std::log10(ms / kFirstEdgeMs)) + 1;
    return static_cast<std::size_t>(std::min(bin, static_cast<double>(kBins - 1)));
  }
  static double upper_edge_ms(std::size_t bin) {
    return kFirstEdgeMs * std::pow(10.0, static_cast<double>(bin) / kBinsPerDecade);
  }

  std::array<std::uint64_t, kBins> bins_{};
  std::uint64_t count_ = 0;
  double max_ms_ = 0;
};

}  // namespace tumble::daemon
