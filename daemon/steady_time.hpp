// The steady clock the daemon stamps arrivals and completions with (never
// stepped by NTP), and the latency of such a stamp.
#pragma once

#include <chrono>
#include <cstdint>

namespace tumble::daemon {

inline std::int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Milliseconds from a steady_now_ns() stamp to now; 0 for an unknown stamp (0).
inline float latency_ms_since(std::int64_t steady_ns) {
  if (steady_ns == 0) return 0.0f;
  return static_cast<float>(static_cast<double>(steady_now_ns() - steady_ns) * 1e-6);
}

}  // namespace tumble::daemon
