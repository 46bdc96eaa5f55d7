// Keeps numbers that are no measurement out of the fuser: one NaN or Inf,
// or a value no MTi can read, would poison every later pose through the
// integration. Clipped values are measurements (the StatusWord flags them
// and the fuser handles them), and a clipped axis can read beyond the
// range (docs/sensors.md: -10.33 rad/s from a 450 deg/s gyro), so the bound is the
// range with a margin, not the range itself.
#pragma once

#include <cstdint>
#include <functional>
#include <string_view>

#include "core/types.hpp"
#include "daemon/rate_limited_log.hpp"

namespace tumble::daemon {

struct ImuLimits {
  double gyro_range_rad_s = 0.0;  // the device's range per axis
  double accel_range_m_s2 = 0.0;
};

// A clipped axis reads at most this many times its range.
inline constexpr double kClippedOvershoot = 1.5;

enum class ImuSampleFault : std::uint8_t {
  None,
  NotFinite,       // NaN or Inf in the time, a rate, an acceleration or the attitude
  BeyondRange,     // an axis beyond kClippedOvershoot times the device's range
  BadOrientation,  // the device's quaternion is not a unit quaternion
};

std::string_view to_string(ImuSampleFault fault);

ImuSampleFault check_imu_sample(const ImuSample& sample, const ImuLimits& limits);

// Between a decoder and the pipeline: passes good samples on, counts the
// others and names them in the log (rate-limited, data time).
class ImuSampleGate {
 public:
  explicit ImuSampleGate(const ImuLimits& limits) : limits_(limits) {}
  void pass(const ImuSample& sample, double arrival_s, const std::function<void(const ImuSample&)>& emit);
  std::int64_t rejected() const { return rejected_; }

 private:
  ImuLimits limits_;
  std::int64_t rejected_ = 0;
  RateLimitedLog log_{1, 10.0};
};

}  // namespace tumble::daemon
