#include "daemon/rate_limited_log.hpp"

#include <algorithm>
#include <cstring>

namespace tumble::daemon {

RateLimitedLog::RateLimitedLog(int max_per_period, double period_s, std::shared_ptr<spdlog::logger> logger)
    : max_per_period_(max_per_period), period_s_(period_s), logger_(std::move(logger)) {}

RateLimitedLog::Entry& RateLimitedLog::find(std::string_view key, double now_s) {
  key = key.substr(0, kMaxKeyLength);
  Entry* oldest = &entries_[0];
  for (Entry& e : entries_) {
    if (e.used && std::string_view(e.key.data(), e.key_length) == key) return e;
    if (!e.used || (oldest->used && e.last_seen_s < oldest->last_seen_s)) oldest = &e;
  }
  Entry& e = *oldest;
  e = Entry{};
  std::memcpy(e.key.data(), key.data(), key.size());
  e.key_length = key.size();
  e.period_start_s = now_s;
  e.used = true;
  return e;
}

bool RateLimitedLog::admit(std::string_view key, double now_s, std::uint64_t& suppressed) {
  Entry& e = find(key, now_s);
  e.last_seen_s = now_s;
  if (now_s - e.period_start_s >= period_s_) {
    e.period_start_s = now_s;
    e.admitted = 0;
  }
  if (e.admitted >= max_per_period_) {
    ++e.suppressed;
    return false;
  }
  ++e.admitted;
  suppressed = e.suppressed;
  e.suppressed = 0;
  return true;
}

}  // namespace tumble::daemon
