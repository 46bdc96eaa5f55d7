#include "daemon/imu_sample_check.hpp"

#include <cmath>

namespace tumble::daemon {

namespace {

bool imu_values_finite(const ImuSample& s) {
  return std::isfinite(s.t_s) && s.accel_m_s2.allFinite() && s.gyro_rad_s.allFinite() &&
         (!s.has_orientation || s.orientation.coeffs().allFinite());
}

bool axes_within_overshoot(const Eigen::Vector3d& v, double range) {
  return v.cwiseAbs().maxCoeff() <= kClippedOvershoot * range;
}

// The MTi sends unit quaternions in single precision at worst.
constexpr double kUnitNormTolerance = 1e-3;

}  // namespace

std::string_view to_string(ImuSampleFault fault) {
  switch (fault) {
    case ImuSampleFault::None: return "none";
    case ImuSampleFault::NotFinite: return "NaN or Inf";
    case ImuSampleFault::BeyondRange: return "beyond the device's range";
    case ImuSampleFault::BadOrientation: return "orientation not a unit quaternion";
  }
  return "unknown";
}

ImuSampleFault check_imu_sample(const ImuSample& sample, const ImuLimits& limits) {
  if (!imu_values_finite(sample)) return ImuSampleFault::NotFinite;
  if (!axes_within_overshoot(sample.gyro_rad_s, limits.gyro_range_rad_s) ||
      !axes_within_overshoot(sample.accel_m_s2, limits.accel_range_m_s2))
    return ImuSampleFault::BeyondRange;
  if (sample.has_orientation && std::abs(sample.orientation.norm() - 1.0) > kUnitNormTolerance)
    return ImuSampleFault::BadOrientation;
  return ImuSampleFault::None;
}

void ImuSampleGate::pass(const ImuSample& sample, double arrival_s, const std::function<void(const ImuSample&)>& emit) {
  const ImuSampleFault fault = check_imu_sample(sample, limits_);
  if (fault == ImuSampleFault::None) {
    emit(sample);
    return;
  }
  ++rejected_;
  log_.warn("imu rejected", arrival_s,
            "imu: sample rejected ({}): gyro [{:.3g}, {:.3g}, {:.3g}] rad/s, accel [{:.3g}, {:.3g}, {:.3g}] m/s^2; "
            "{} so far",
            to_string(fault), sample.gyro_rad_s.x(), sample.gyro_rad_s.y(), sample.gyro_rad_s.z(),
            sample.accel_m_s2.x(), sample.accel_m_s2.y(), sample.accel_m_s2.z(), rejected_);
}

}  // namespace tumble::daemon
