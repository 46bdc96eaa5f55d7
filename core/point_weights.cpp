// See point_weights.hpp for the models and the authors' details followed.
#include "core/point_weights.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/rotation.hpp"

namespace tumble {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

void require_size(std::size_t expected, std::size_t actual, const char* what) {
  if (expected != actual) {
    throw std::invalid_argument(std::string("compute_point_weights: ") + what + " has " + std::to_string(actual) +
                                " entries for " + std::to_string(expected) + " points");
  }
}

double wrap_angle(double angle_rad) {
  return std::remainder(angle_rad, 2.0 * std::numbers::pi);  // (−π, π]
}

double azimuth_of(const Eigen::Vector3d& p) { return std::atan2(p.y(), p.x()); }

// The 4 variants rot(p, sθ) + s'δ, in the order (+,+), (+,−), (−,+), (−,−).
std::array<Eigen::Vector3d, 4> perturbed_positions(const Eigen::Vector3d& p, const SkewPerturbation& perturbation) {
  const AxisAngle rotation(perturbation.theta_rad);
  const Eigen::Vector3d forward = rotation.rotate(p, 1.0);
  const Eigen::Vector3d backward = rotation.rotate(p, -1.0);
  return {forward + perturbation.delta_m, forward - perturbation.delta_m, backward + perturbation.delta_m,
          backward - perturbation.delta_m};
}

// Q1 and Q3 as the authors take them: the ⌈n/4⌉-th and ⌈3n/4⌉-th smallest.
std::pair<double, double> quartiles(std::vector<double>& values) {
  const std::size_t n = values.size();
  const auto q1_index = static_cast<std::size_t>(std::ceil(static_cast<double>(n) / 4.0)) - 1;
  const auto q3_index = static_cast<std::size_t>(std::ceil(3.0 * static_cast<double>(n) / 4.0)) - 1;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(q3_index), values.end());
  const double q3 = values[q3_index];
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(q1_index),
                   values.begin() + static_cast<std::ptrdiff_t>(q3_index));
  return {values[q1_index], q3};
}

// Marks (difference array over the azimuth-sorted ring) every point whose
// azimuth lies in [from, to] (both in (−π, π], possibly wrapping through ±π).
void mark_azimuth_span(const std::vector<std::pair<double, std::uint32_t>>& sorted, double from, double to,
                       std::vector<int>& marks) {
  auto mark_range = [&](double lo, double hi) {
    const auto begin = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(lo, std::uint32_t{0}));
    const auto end = std::upper_bound(sorted.begin(), sorted.end(),
                                      std::make_pair(hi, std::numeric_limits<std::uint32_t>::max()));
    if (begin >= end) return;
    ++marks[static_cast<std::size_t>(begin - sorted.begin())];
    --marks[static_cast<std::size_t>(end - sorted.begin())];
  };
  if (from <= to) {
    mark_range(from, to);
  } else {
    mark_range(from, std::numbers::pi);
    mark_range(-std::numbers::pi, to);
  }
}

// GVTW's corner term on the finished σ_s (see the header).
void add_corner_uncertainty(const PointWeightParams& params, const Trajectory& trajectory,
                            const PointWeightInput& input, std::span<double> sigma_s_m,
                            PointWeightWorkspace& workspace) {
  const std::size_t n = input.points_l.size();
  // Counting sort by ring (stable), then by time within each ring.
  std::array<std::uint32_t, 257> ring_begin{};
  for (const std::uint8_t ring : input.rings) ++ring_begin[ring + 1u];
  for (std::size_t r = 1; r < ring_begin.size(); ++r) ring_begin[r] += ring_begin[r - 1];
  std::array<std::uint32_t, 256> fill{};
  std::copy(ring_begin.begin(), ring_begin.end() - 1, fill.begin());
  workspace.ring_order.resize(n);
  for (std::size_t i = 0; i < n; ++i) workspace.ring_order[fill[input.rings[i]]++] = static_cast<std::uint32_t>(i);

  std::size_t hint = 0;
  const SkewPerturbation start = trajectory.cumulative_skew(input.t_scan_start_s, input.deskewed, hint);
  auto by_time = [&](std::uint32_t a, std::uint32_t b) {
    return input.times_s[a] < input.times_s[b] || (input.times_s[a] == input.times_s[b] && a < b);
  };
  for (std::size_t r = 0; r < 256; ++r) {
    const auto begin = workspace.ring_order.begin() + ring_begin[r];
    const auto end = workspace.ring_order.begin() + ring_begin[r + 1];
    if (end - begin < 2) continue;
    if (!std::is_sorted(begin, end, by_time)) std::sort(begin, end, by_time);

    // Jumps of σ_s between consecutive finite values; the first counts as 0.
    workspace.jumps.clear();
    workspace.azimuths.clear();
    double previous = std::numeric_limits<double>::quiet_NaN();
    for (auto it = begin; it != end; ++it) {
      const double sigma = sigma_s_m[*it];
      if (!std::isfinite(sigma)) continue;
      workspace.jumps.push_back(std::isnan(previous) ? 0.0 : std::abs(sigma - previous));
      workspace.azimuths.emplace_back(azimuth_of(input.points_l[*it]), *it);
      previous = sigma;
    }
    if (workspace.jumps.size() < 2) continue;
    workspace.jumps_sorted.assign(workspace.jumps.begin(), workspace.jumps.end());
    const auto [q1, q3] = quartiles(workspace.jumps_sorted);
    const double threshold = q3 + params.corner_iqr_factor * (q3 - q1);

    workspace.corner_points.clear();
    for (std::size_t j = 0; j < workspace.jumps.size(); ++j) {
      if (workspace.jumps[j] > threshold) workspace.corner_points.push_back(workspace.azimuths[j].second);
    }
    if (workspace.corner_points.empty()) continue;

    // azimuths was in time order (matching jumps); sorted from here on.
    std::sort(workspace.azimuths.begin(), workspace.azimuths.end());
    workspace.span_marks.assign(workspace.azimuths.size() + 1, 0);
    for (const std::uint32_t i : workspace.corner_points) {
      const Eigen::Vector3d& p = input.points_l[i];
      const SkewPerturbation at = trajectory.cumulative_skew(input.times_s[i], input.deskewed, hint);
      const SkewPerturbation perturbation{at.delta_m - start.delta_m, at.theta_rad - start.theta_rad};
      const double azimuth = azimuth_of(p);
      double lo = kInfinity, hi = -kInfinity;
      for (const Eigen::Vector3d& q : perturbed_positions(p, perturbation)) {
        const double offset = wrap_angle(azimuth_of(q) - azimuth);
        lo = std::min(lo, offset);
        hi = std::max(hi, offset);
      }
      mark_azimuth_span(workspace.azimuths, wrap_angle(azimuth + lo), wrap_angle(azimuth + hi), workspace.span_marks);
    }
    int inside = 0;
    for (std::size_t j = 0; j < workspace.azimuths.size(); ++j) {
      inside += workspace.span_marks[j];
      if (inside > 0) sigma_s_m[workspace.azimuths[j].second] += params.corner_point_uncertainty_m;
    }
  }
}

}  // namespace

std::optional<WeightModel> weight_model_from_name(std::string_view name) {
  for (const WeightModel model :
       {WeightModel::NM, WeightModel::TW, WeightModel::VTW, WeightModel::GVTW, WeightModel::SAW}) {
    if (weight_model_name(model) == name) return model;
  }
  return std::nullopt;
}

std::string_view weight_model_name(WeightModel model) {
  switch (model) {
    case WeightModel::NM: return "NM";
    case WeightModel::TW: return "TW";
    case WeightModel::VTW: return "VTW";
    case WeightModel::GVTW: return "GVTW";
    case WeightModel::SAW: return "SAW";
  }
  return "?";
}

double sensor_noise_sigma(double range_m, const PointWeightParams& params) {
  return std::max(params.sensor_noise_min_m, params.sensor_noise_rad * range_m);
}

double vtw_max_spread(const Eigen::Vector3d& p, const SkewPerturbation& perturbation) {
  const std::array<Eigen::Vector3d, 4> v = perturbed_positions(p, perturbation);
  double max_squared = 0.0;
  for (std::size_t a = 0; a < 4; ++a) {
    for (std::size_t b = a + 1; b < 4; ++b) max_squared = std::max(max_squared, (v[a] - v[b]).squaredNorm());
  }
  return std::sqrt(max_squared);
}

double gvtw_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, const Eigen::Vector3d& theta_rad,
                     const Eigen::Vector3d& delta_m, double min_abs_cos) {
  const AxisAngle rotation(theta_rad);
  const double cos_incidence = rotation.rotate(p / p.norm(), 1.0).dot(normal);
  const double guarded = std::copysign(std::max(std::abs(cos_incidence), min_abs_cos), cos_incidence);
  return (p - rotation.rotate(delta_m, 1.0)).dot(normal) / guarded;
}

double gvtw_max_spread(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, const SkewPerturbation& perturbation,
                       double min_abs_cos) {
  // Same as gvtw_distance for the 4 sign combinations, sharing one sin/cos.
  // The max of |d_a − d_b| over the 6 pairs is max(d) − min(d).
  if (!(normal.squaredNorm() > 0.25)) return kInfinity;  // zero or NaN: unknown
  const AxisAngle rotation(perturbation.theta_rad);
  const Eigen::Vector3d direction = p / p.norm();
  const double p_along_normal = p.dot(normal);
  double lo = kInfinity, hi = -kInfinity;
  for (const double s : {1.0, -1.0}) {
    const double cos_incidence = rotation.rotate(direction, s).dot(normal);
    const double guarded = std::copysign(std::max(std::abs(cos_incidence), min_abs_cos), cos_incidence);
    const double delta_along_normal = rotation.rotate(perturbation.delta_m, s).dot(normal);
    for (const double s_prime : {1.0, -1.0}) {
      const double d = (p_along_normal - s_prime * delta_along_normal) / guarded;
      if (std::isnan(d)) return kInfinity;
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  }
  return hi - lo;
}

double saw_weight(double scan_angle_rad, double curvature, double reference_curvature) {
  const double angle_part = std::cos(scan_angle_rad / 4.0);
  const double curvature_part = std::max(0.25, std::min(curvature / reference_curvature, 1.0));
  return std::max(angle_part, curvature_part);
}

void compute_point_weights(const PointWeightParams& params, const Trajectory& trajectory,
                           const PointWeightInput& input, PointWeightOutput output, PointWeightWorkspace& workspace) {
  const std::size_t n = input.points_l.size();
  require_size(n, input.times_s.size(), "times_s");
  require_size(n, output.sigma_n_m.size(), "sigma_n_m");
  require_size(n, output.sigma_s_m.size(), "sigma_s_m");
  require_size(n, output.weights.size(), "weights");
  const bool corner_term = params.model == WeightModel::GVTW && params.corner_point_uncertainty_m != 0.0;
  if (params.model == WeightModel::GVTW) require_size(n, input.normals.size(), "normals");
  if (params.model == WeightModel::SAW) require_size(n, input.curvatures.size(), "curvatures");
  if (corner_term) require_size(n, input.rings.size(), "rings");
  if (n == 0) return;

  for (std::size_t i = 0; i < n; ++i) output.sigma_n_m[i] = sensor_noise_sigma(input.points_l[i].norm(), params);

  switch (params.model) {
    case WeightModel::NM:
      std::fill(output.sigma_s_m.begin(), output.sigma_s_m.end(), 0.0);
      break;
    case WeightModel::TW:
      for (std::size_t i = 0; i < n; ++i) {
        output.sigma_s_m[i] = params.tw_c1_m_s * std::abs(input.times_s[i] - input.t_scan_start_s);
      }
      break;
    case WeightModel::VTW: {
      SkewIntegrator skew(trajectory, input.t_scan_start_s, input.deskewed);
      for (std::size_t i = 0; i < n; ++i) {
        output.sigma_s_m[i] = 0.5 * params.vtw_c2 * vtw_max_spread(input.points_l[i], skew.until(input.times_s[i]));
      }
      break;
    }
    case WeightModel::GVTW: {
      SkewIntegrator skew(trajectory, input.t_scan_start_s, input.deskewed);
      for (std::size_t i = 0; i < n; ++i) {
        output.sigma_s_m[i] = 0.5 * params.gvtw_c3 *
                              gvtw_max_spread(input.points_l[i], input.normals[i], skew.until(input.times_s[i]),
                                              params.gvtw_min_abs_cos);
      }
      if (corner_term) add_corner_uncertainty(params, trajectory, input, output.sigma_s_m, workspace);
      break;
    }
    case WeightModel::SAW: {
      const double t_last = std::isnan(input.t_scan_end_s)
                                ? *std::max_element(input.times_s.begin(), input.times_s.end())
                                : input.t_scan_end_s;
      const double duration = t_last - input.t_scan_start_s;
      for (std::size_t i = 0; i < n; ++i) {
        const double scan_angle =
            duration > 0.0 ? 2.0 * std::numbers::pi * (input.times_s[i] - input.t_scan_start_s) / duration : 0.0;
        output.sigma_s_m[i] = 0.0;
        output.weights[i] = saw_weight(scan_angle, input.curvatures[i], params.saw_reference_curvature);
      }
      return;
    }
  }
  std::fill(output.weights.begin(), output.weights.end(), 1.0);
}

}  // namespace tumble
