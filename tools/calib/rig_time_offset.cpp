#include "tools/calib/rig_time_offset.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "tools/calib/rig_gyro.hpp"

namespace tumble::calib {
namespace {

std::vector<double> offset_grid(double centre_s, double half_width_s, double step_s) {
  const int steps = static_cast<int>(std::round(half_width_s / step_s));
  std::vector<double> grid;
  for (int i = -steps; i <= steps; ++i) grid.push_back(centre_s + i * step_s);
  return grid;
}

Eigen::Vector3d rotation_vector(const Eigen::Quaterniond& q) {
  const Eigen::AngleAxisd aa(q);
  return aa.angle() * aa.axis();
}

}  // namespace

std::vector<RotationIncrement> rotation_increments(std::span<const LidarRotation> lidar,
                                                   std::span<const ImuSample> imu, double offset_s) {
  std::vector<RotationIncrement> out;
  out.reserve(lidar.size());
  const GyroTiming timing{.offset_s = offset_s};
  for (const LidarRotation& l : lidar)
    out.push_back({l.rotation_rad, rotation_vector(gyro_rotation(imu, timing, l.t0_s, l.t1_s)), l.t1_s - l.t0_s});
  return out;
}

double magnitude_correlation(std::span<const LidarRotation> lidar, std::span<const ImuSample> imu, double offset_s) {
  const std::vector<RotationIncrement> inc = rotation_increments(lidar, imu, offset_s);
  const double n = static_cast<double>(inc.size());
  if (inc.size() < 2) return 0.0;
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (const RotationIncrement& r : inc) {
    const double x = r.lidar_rad.norm(), y = r.gyro_rad.norm();
    sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y;
  }
  const double cov = sxy - sx * sy / n, vx = sxx - sx * sx / n, vy = syy - sy * sy / n;
  return vx > 0 && vy > 0 ? cov / std::sqrt(vx * vy) : 0.0;
}

TimeOffsetEstimate coarse_time_offset(std::span<const LidarRotation> lidar, std::span<const ImuSample> imu,
                                      double centre_s, double half_width_s, double step_s) {
  const std::vector<double> grid = offset_grid(centre_s, half_width_s, step_s);
  TimeOffsetEstimate best{.offset_s = centre_s, .score = -2.0};
  std::size_t best_i = 0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const double c = magnitude_correlation(lidar, imu, grid[i]);
    if (c > best.score) best = {.offset_s = grid[i], .score = c}, best_i = i;
  }
  best.at_edge = best_i == 0 || best_i + 1 == grid.size();
  return best;
}

TimeOffsetEstimate fine_time_offset(std::span<const LidarRotation> lidar, std::span<const ImuSample> imu,
                                    double centre_s, double half_width_s, double step_s, bool reject_outliers) {
  const std::vector<double> grid = offset_grid(centre_s, half_width_s, step_s);
  std::vector<double> ssr(grid.size());
  std::vector<std::size_t> used(grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const HandEyeRotation fit = align_rotation_increments(rotation_increments(lidar, imu, grid[i]), reject_outliers);
    ssr[i] = fit.used > 0 ? fit.sum_squared_residual_rad2 / static_cast<double>(fit.used) : 1e300;
    used[i] = fit.used;
  }
  std::size_t b = 0;
  for (std::size_t i = 1; i < grid.size(); ++i)
    if (ssr[i] < ssr[b]) b = i;
  TimeOffsetEstimate out{.offset_s = grid[b], .score = ssr[b]};
  if (b == 0 || b + 1 == grid.size()) {
    out.at_edge = true;
    return out;
  }
  // Parabola through (−h, y0), (0, y1), (h, y2): vertex at h (y0 − y2) / (2 (y0 − 2 y1 + y2)).
  const double y0 = ssr[b - 1], y1 = ssr[b], y2 = ssr[b + 1];
  const double curvature = (y0 - 2.0 * y1 + y2) / (step_s * step_s);  // d²(mean SSR)/dτ²
  if (curvature <= 0) return out;
  out.offset_s = grid[b] + 0.5 * step_s * (y0 - y2) / (y0 - 2.0 * y1 + y2);
  // SSR(τ) = n·mean; for a least-squares cost the variance of the minimiser
  // is 2 σ² / SSR''(τ), with σ² = SSR / (3n − dof) ≈ mean / 3 per axis.
  const double n = static_cast<double>(used[b]);
  const double sigma2 = y1 / 3.0;
  out.sigma_s = std::sqrt(2.0 * sigma2 / (n * curvature));
  return out;
}

}  // namespace tumble::calib
