// Warnings that may repeat at sensor rate (a bad packet every millisecond)
// are let through at most max_per_period times per period and key; the next
// line that gets through says how many were suppressed. One instance per
// thread (no locking); time is passed in, so tests need no clock.
#pragma once

#include <fmt/format.h>
#include <spdlog/logger.h>
#include <spdlog/spdlog.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>
#include <utility>

namespace tumble::daemon {

class RateLimitedLog {
 public:
  static constexpr std::size_t kMaxKeys = 32;  // beyond this, the least recently active key is forgotten
  static constexpr std::size_t kMaxKeyLength = 47;

  RateLimitedLog(int max_per_period, double period_s,
                 std::shared_ptr<spdlog::logger> logger = spdlog::default_logger());

  template <class... Args>
  void warn(std::string_view key, double now_s, fmt::format_string<Args...> format, Args&&... args) {
    std::uint64_t suppressed = 0;
    if (!admit(key, now_s, suppressed)) return;
    if (suppressed == 0) {
      logger_->warn(format, std::forward<Args>(args)...);
    } else {
      logger_->warn("{} ({} similar suppressed)", fmt::format(format, std::forward<Args>(args)...), suppressed);
    }
  }

  // True when a line for key may be logged at now_s; suppressed = lines held
  // back for this key since the last one that got through.
  bool admit(std::string_view key, double now_s, std::uint64_t& suppressed);

 private:
  struct Entry {
    std::array<char, kMaxKeyLength> key{};
    std::size_t key_length = 0;
    double period_start_s = 0.0;
    double last_seen_s = 0.0;
    int admitted = 0;
    std::uint64_t suppressed = 0;
    bool used = false;
  };
  Entry& find(std::string_view key, double now_s);

  int max_per_period_;
  double period_s_;
  std::shared_ptr<spdlog::logger> logger_;
  std::array<Entry, kMaxKeys> entries_{};
};

}  // namespace tumble::daemon
