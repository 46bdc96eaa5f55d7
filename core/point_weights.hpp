// Point weights for the weighted point-to-plane cost (paper §III-C,
// docs/method.md §3):  J = Σ w (e·n)²,  w = 1/(σ_n² + σ_s²).
//
//   σ_n  sensor noise growing with the beam footprint: max(0.02 m, 0.0015 rad · range)
//   σ_s  skew uncertainty, one of:
//     NM    0
//     TW    c1 · (t_i − t_start)                          (grows linearly in the scan)
//     VTW   c2/2 · max_{a,b∈V_i} ‖a − b‖,  V_i = {rot(p, sθ) + s'δ : s, s' = ±1}
//     GVTW  c3/2 · max_{a,b} |d_a − d_b|,   d = ((p − rot(δ, θ))·n) / (rot(p/‖p‖, θ)·n)
//   SAW  (Al-Nuaimi 2016 baseline) gives the weight itself:
//          w = max(cos(γ/4), max(0.25, min(c/c_r, 1)))
//
// δ, θ = ∫σ_v dt, ∫σ_ω dt per lidar axis from the scan start to the point's
// time (trajectory.hpp), with the de-skewed σ pair (log-normal / cubic) when
// the scan was de-skewed and 0.14|v| / 0.72|ω| otherwise.
//
// Details from the authors' implementation (their libpointmatcher NoiseSkew),
// which the paper leaves implicit, are followed: Rodrigues rotation, the max
// over the 6 unordered pairs of the 4 variants, GVTW's grazing guard
// |rot(p/‖p‖, θ)·n| ≥ 1e-3 (sign kept), a NaN distance (unknown normal, point
// at the origin) meaning σ_s = ∞ and so a zero match weight (ours: a zero-length
// normal, the registration's "no normal", counts as unknown too), SAW's γ = 2π · (t − t_start) /
// (t_last − t_start) (the angle swept since the scan start, from the times),
// and GVTW's optional "corner" term: per ring, in firing order, a jump of σ_s
// between consecutive points larger than Q3 + 15·IQR of the ring's jumps marks
// a corner; the ring's points whose azimuth lies in the span of the corner's 4
// perturbed positions get corner_point_uncertainty_m added (default 0, as in
// the paper's runs). Ours: jumps are taken between finite σ's only, and the
// azimuth span wraps correctly at ±π.
//
// σ_n and the GVTW beam use ‖p‖ of the points as given; after de-skewing that
// is the distance from the scan-start origin, not the firing origin — the
// difference (the lidar's motion within one scan) is what σ_s models.
//
// Per point: O(1), no allocation (outputs are caller-owned spans; the corner
// term's buffers live in a reusable workspace that only grows).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/trajectory.hpp"

namespace tumble {

enum class WeightModel { NM, TW, VTW, GVTW, SAW };

// "NM", "TW", "VTW", "GVTW", "SAW" (case-sensitive, the paper's names).
std::optional<WeightModel> weight_model_from_name(std::string_view name);
std::string_view weight_model_name(WeightModel model);

struct PointWeightParams {
  WeightModel model = WeightModel::GVTW;
  double tw_c1_m_s = 0.25;
  double vtw_c2 = 2.0;
  double gvtw_c3 = 4.0;
  // c_r: the curvature (λ_min / Σλ, at most 1/3) of a "highly curved"
  // surface. Environment-dependent; the paper gives no value. 0.1 is well
  // above planes (~0) and below isotropic scatter (1/3).
  double saw_reference_curvature = 0.1;
  double sensor_noise_min_m = 0.02;
  double sensor_noise_rad = 0.0015;
  double gvtw_min_abs_cos = 1e-3;  // grazing guard on the GVTW denominator
  double corner_point_uncertainty_m = 0.0;
  double corner_iqr_factor = 15.0;
  double map_max_sigma_m = 1.0;
};

// Per-point inputs, all the same length as points_l (spans a model does not
// use may be empty: normals for GVTW, curvatures for SAW, rings for GVTW with
// a non-zero corner term).
struct PointWeightInput {
  std::span<const Eigen::Vector3d> points_l;  // de-skewed (scan-start frame) or raw
  std::span<const double> times_s;
  std::span<const Eigen::Vector3d> normals;   // unit; zero or NaN where unknown (→ σ_s = ∞ under GVTW)
  std::span<const double> curvatures;
  std::span<const std::uint8_t> rings;        // laser index (LidarPoint::laser)
  double t_scan_start_s = 0.0;
  bool deskewed = true;                       // selects the σ_v/σ_ω pair
  // SAW's t_last: the scan's last point time. NaN: the latest of times_s (a
  // caller weighing a subset of the scan passes the whole scan's).
  double t_scan_end_s = std::numeric_limits<double>::quiet_NaN();
};

// Caller-owned outputs, each the length of the input (PointCloud's
// sigma_n_m, sigma_s_m and weights fit). The models NM/TW/VTW/GVTW produce
// σ_s (the registration combines reading and map σ's into 1/(Σσ²)); their
// weight is 1. SAW produces the weight itself, and σ_s = 0.
struct PointWeightOutput {
  std::span<double> sigma_n_m;
  std::span<double> sigma_s_m;
  std::span<double> weights;
};

// Buffers of the GVTW corner term, reused across scans (they grow to the
// largest scan seen, then never allocate again).
struct PointWeightWorkspace {
  std::vector<std::uint32_t> ring_order;              // point indices by ring, then time
  std::vector<double> jumps;                          // |Δσ_s| along one ring
  std::vector<double> jumps_sorted;
  std::vector<std::uint32_t> corner_points;           // point indices of the ring's corners
  std::vector<std::pair<double, std::uint32_t>> azimuths;  // (azimuth, point index), one ring, sorted
  std::vector<int> span_marks;                        // difference array over `azimuths`
};

void compute_point_weights(const PointWeightParams& params, const Trajectory& trajectory,
                           const PointWeightInput& input, PointWeightOutput output, PointWeightWorkspace& workspace);

// The pieces, for tests and for callers with their own loop.
double sensor_noise_sigma(double range_m, const PointWeightParams& params);
// max over the 6 pairs of ‖a − b‖ (VTW), before the c2/2 factor.
double vtw_max_spread(const Eigen::Vector3d& p, const SkewPerturbation& perturbation);
// max over the 6 pairs of |d_a − d_b| (GVTW), before the c3/2 factor; +∞ when
// a distance is NaN or the normal is unknown (not of unit length).
double gvtw_max_spread(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, const SkewPerturbation& perturbation,
                       double min_abs_cos);
// d(p, θ, δ, n) of one variant (theta/delta already carry their signs).
double gvtw_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, const Eigen::Vector3d& theta_rad,
                     const Eigen::Vector3d& delta_m, double min_abs_cos);
double saw_weight(double scan_angle_rad, double curvature, double reference_curvature);

// The map insert's cut (paper: points with σ_s above 1 m are not inserted);
// false for σ_s = ∞ or NaN.
inline bool keep_in_map(double sigma_s_m, const PointWeightParams& params) {
  return sigma_s_m <= params.map_max_sigma_m;
}

}  // namespace tumble
