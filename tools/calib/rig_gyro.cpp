#include "tools/calib/rig_gyro.hpp"

#include <algorithm>

#include "core/rotation.hpp"

namespace tumble::calib {
namespace {

// First sample whose corrected time is after t_s.
std::size_t first_after(std::span<const ImuSample> samples, const GyroTiming& timing, double t_s) {
  const auto it = std::upper_bound(samples.begin(), samples.end(), t_s - timing.offset_s,
                                   [](double t, const ImuSample& s) { return t < s.t_s; });
  return static_cast<std::size_t>(it - samples.begin());
}

}  // namespace

Eigen::Vector3d gyro_rate_at(std::span<const ImuSample> samples, const GyroTiming& timing, double t_s) {
  if (samples.empty()) return Eigen::Vector3d::Zero();
  const std::size_t j = first_after(samples, timing, t_s);
  if (j == 0) return samples.front().gyro_rad_s - timing.bias_rad_s;
  if (j == samples.size()) return samples.back().gyro_rad_s - timing.bias_rad_s;
  const ImuSample& a = samples[j - 1];
  const ImuSample& b = samples[j];
  const double u = (t_s - timing.offset_s - a.t_s) / (b.t_s - a.t_s);
  return (1.0 - u) * a.gyro_rad_s + u * b.gyro_rad_s - timing.bias_rad_s;
}

Eigen::Quaterniond gyro_rotation(std::span<const ImuSample> samples, const GyroTiming& timing, double t0_s,
                                 double t1_s) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  if (samples.empty() || !(t1_s > t0_s)) return q;
  double t = t0_s;
  Eigen::Vector3d rate = gyro_rate_at(samples, timing, t);
  for (std::size_t j = first_after(samples, timing, t0_s); t < t1_s; ++j) {
    const double t_next = j < samples.size() ? std::min(samples[j].t_s + timing.offset_s, t1_s) : t1_s;
    const Eigen::Vector3d rate_next = gyro_rate_at(samples, timing, t_next);
    q = integrate_body_rate(q, 0.5 * (rate + rate_next), t_next - t);
    t = t_next;
    rate = rate_next;
  }
  return q;
}

}  // namespace tumble::calib
