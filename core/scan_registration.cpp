#include "core/scan_registration.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "core/deskew.hpp"
#include "core/registration_confidence.hpp"

namespace tumble {

namespace {

// Whether a clipped gyro or accelerometer touched the motion from t_from_s
// on: the prediction over it is then a guess (a rate beyond the gyro's range
// taken from the lidar's last scans, a speed lost in a shock), not a
// measurement to hold ICP to (docs/decisions/prediction-prior.md).
bool clipped_since(const Trajectory& trajectory, double t_from_s) {
  for (std::size_t i = trajectory.size(); i > 0 && trajectory[i - 1].t_s >= t_from_s; --i) {
    const std::array<bool, 3>& s = trajectory[i - 1].saturated;
    if (s[0] || s[1] || s[2]) return true;
  }
  return false;
}

IcpParams icp_params_for(const OdometryParams& p) {
  IcpParams icp = p.icp;
  icp.weighting = p.weights.model == WeightModel::SAW ? MatchWeighting::kPointWeight : MatchWeighting::kInverseVariance;
  return icp;
}

const OdometryParams& checked(const OdometryParams& p) {
  check_odometry_params(p);
  return p;
}

}  // namespace

void check_odometry_params(const OdometryParams& p) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("OdometryParams: " + what); };
  check_position_uncertainty_params(p.position);
  if (p.max_pending_scans < 1) fail("max_pending_scans must be >= 1");
  if (p.weights.map_max_sigma_m != p.map.max_sigma_s_m)
    fail("weights.map_max_sigma_m (" + std::to_string(p.weights.map_max_sigma_m) + ") and map.max_sigma_s_m (" +
         std::to_string(p.map.max_sigma_s_m) + ") must be equal");
  if (!(p.min_position_sigma_m > 0)) fail("min_position_sigma_m must be > 0");
  if (!(p.registration_voxel_size_m >= 0)) fail("registration_voxel_size_m must be >= 0");
}

ScanRegistration::ScanRegistration(const OdometryParams& params, Clock clock, ParallelRunner& runner)
    : params_(checked(params)),
      clock_(std::move(clock)),
      runner_(runner),
      downsampler_(params.voxel_size_m),
      normals_(params.reading_normals, runner),
      line_normals_(params.reading_normals, params.scan_line_window, runner),
      icp_(icp_params_for(params), clock_, runner),
      map_(params.map, runner),
      seen_through_(params.seen_through, runner),
      unobserved_direction_(params.unobserved),
      position_uncertainty_(params.position),
      registration_selector_(std::max(params.registration_voxel_size_m, params.voxel_size_m)) {}

ScanCorrection scan_correction_of(const ScanResult& result) {
  return {.t_start_s = result.t_scan_start_s,
          .t_end_s = result.t_scan_end_s,
          .T_wl = result.T_wl,
          .position_sigma_m = result.position_sigma_m,
          .position_var_w_m2 = result.position_var_w_m2,
          .jumped = result.jumped,
          .map_start = result.map_initialised,
          .expected_error_m = result.expected_error_icp_m,
          .expected_rotation_error_rad = result.expected_rotation_error_icp_rad,
          .unmeasured_w = result.held_translation_w};
}

void ScanRegistration::reset_map() {
  map_ = LocalMap(params_.map, runner_);
  position_uncertainty_.reset(last_scan_start_s_);
}

ScanOutcome ScanRegistration::process(const Scan& scan, const Trajectory& trajectory, ScanResult& result) {
  return process(scan, trajectory, result, ScanConditions{.deskew = params_.deskew});
}

ScanOutcome ScanRegistration::process(const Scan& scan, const Trajectory& trajectory, ScanResult& result,
                                      const ScanConditions& conditions) {
  const double t_start = scan.points.front().t_s;
  if (t_start <= last_scan_start_s_) return ScanOutcome::OutOfOrder;
  last_scan_start_s_ = t_start;
  result = ScanResult{};
  result.scan_index = scan.index;
  result.t_scan_start_s = t_start;
  result.t_scan_end_s = scan.points.back().t_s;
  result.points_in = scan.points.size();
  StageTimings& timing = result.timings;
  timing.measured = static_cast<bool>(clock_);
  const double clock_start = now();
  lap_mark_ = clock_start;

  deskew(scan, trajectory, conditions.deskew);
  lap(timing.deskew_s);
  downsample(result);
  lap(timing.downsample_s);
  if (reading_.size() < params_.min_scan_points) return ScanOutcome::TooSmall;

  const ScanInputs in{.trajectory = trajectory,
                      .conditions = conditions,
                      .t_start_s = t_start,
                      .t_last_s = *std::max_element(reading_.times_s.begin(), reading_.times_s.end())};
  fit_registered_normals(scan);
  lap(timing.normals_s);
  weigh_registered(in);
  lap(timing.weights_s);

  const Eigen::Isometry3d predicted = trajectory.pose_at(t_start);
  // The prediction is no better than the velocity that carried it (PositionUncertainty).
  const Eigen::Vector3d velocity_var_w = trajectory.velocity_variance_at(t_start);
  result.T_wl = predicted;
  if (map_.empty()) {
    result.map_initialised = true;
    result.registered = true;
  } else {
    align_to_map(in, predicted, velocity_var_w, result);
  }
  estimate_uncertainty(in, velocity_var_w, result);
  lap(timing.registration_s);

  // A jump is not in the map, whose points must stay where the scans that agree put them.
  const bool update_map = result.registered && !result.jumped;
  if (update_map && conditions.deskew && conditions.trajectory_measured && !map_.empty() &&
      params_.seen_through.enabled && result.expected_error_icp_m <= params_.seen_through.max_expected_error_m) {
    // Before the scan's own points go in: they lie at its beams' ends.
    remove_seen_through(in, result);
    lap(timing.seen_through_s);
  }
  if (update_map) add_to_map(in, result);
  result.map_points = map_.size();
  lap(timing.map_update_s);
  timing.total_s = lap_mark_ - clock_start;
  return ScanOutcome::Registered;
}

void ScanRegistration::lap(double& stage_s) {
  const double t = now();
  stage_s += t - lap_mark_;
  lap_mark_ = t;
}

// Into the lidar frame at the scan's first point.
void ScanRegistration::deskew(const Scan& scan, const Trajectory& trajectory, bool along_trajectory) {
  const std::size_t n = scan.points.size();
  raw_.resize(n);
  deskew_scan(scan, trajectory, along_trajectory, raw_.points);
  for (std::size_t i = 0; i < n; ++i) {
    raw_.times_s[i] = scan.points[i].t_s;
    raw_.rings[i] = scan.points[i].laser;
  }
}

void ScanRegistration::downsample(ScanResult& result) {
  downsampler_.apply(raw_, reading_);
  result.points_downsampled = reading_.size();
  if (params_.registration_voxel_size_m > params_.voxel_size_m) {
    registration_selector_.select(reading_.points, registered_indices_);
  } else {
    registered_indices_.resize(reading_.size());
    for (std::size_t i = 0; i < reading_.size(); ++i) registered_indices_[i] = static_cast<std::uint32_t>(i);
  }
  result.points_registered = registered_indices_.size();
}

// Normals and σ's are costly per point and needed only for the points ICP
// registers and the points the map will take (few, in steady state): each
// is fitted from the whole down-sampled cloud, once. The GVTW corner term
// compares the σ's of neighbouring points along a ring, so with it every
// point gets its σ (and so its normal) first.
bool ScanRegistration::weighs_whole_scan() const {
  return params_.weights.model == WeightModel::GVTW && params_.weights.corner_point_uncertainty_m != 0.0;
}

bool ScanRegistration::normals_from_scan_lines() const {
  return params_.reading_normal_source == ReadingNormalSource::kScanLines;
}

void ScanRegistration::fit_registered_normals(const Scan& scan) {
  if (normals_from_scan_lines()) {
    ring_elevations_rad(scan, ring_elevations_rad_);
    line_normals_.index(reading_, ring_elevations_rad_);
  } else {
    normals_.index(reading_);
  }
  normal_done_.assign(reading_.size(), 0);
  if (weighs_whole_scan()) {
    all_indices_.resize(reading_.size());
    std::iota(all_indices_.begin(), all_indices_.end(), std::uint32_t{0});
    fit_normals(all_indices_);
  } else {
    fit_normals(registered_indices_);
  }
}

void ScanRegistration::fit_normals(std::span<const std::uint32_t> indices) {
  normals_todo_.clear();
  for (const std::uint32_t i : indices) {
    if (normal_done_[i]) continue;
    normal_done_[i] = 1;
    normals_todo_.push_back(i);
  }
  if (normals_from_scan_lines()) {
    line_normals_.estimate(reading_, Eigen::Vector3d::Zero(), normals_todo_);
  } else {
    normals_.estimate(reading_, Eigen::Vector3d::Zero(), normals_todo_);
  }
}

void ScanRegistration::weigh_registered(const ScanInputs& in) {
  if (weighs_whole_scan()) weigh(in, reading_);
  gather(registered_indices_, registered_);
  if (!weighs_whole_scan()) weigh(in, registered_);
}

void ScanRegistration::weigh(const ScanInputs& in, PointCloud& cloud) {
  PointWeightInput input;
  input.points_l = cloud.points;
  input.times_s = cloud.times_s;
  input.normals = cloud.normals;
  input.curvatures = cloud.curvatures;
  input.rings = cloud.rings;
  input.t_scan_start_s = in.t_start_s;
  input.t_scan_end_s = in.t_last_s;
  input.deskewed = in.conditions.deskew && in.conditions.trajectory_measured;
  compute_point_weights(params_.weights, in.trajectory, input,
                        PointWeightOutput{cloud.sigma_n_m, cloud.sigma_s_m, cloud.weights}, weight_workspace_);
}

void ScanRegistration::gather(std::span<const std::uint32_t> indices, PointCloud& out) const {
  out.resize(indices.size());
  for (std::size_t j = 0; j < indices.size(); ++j) out.copy_point(j, reading_, indices[j]);
}

void ScanRegistration::align_to_map(const ScanInputs& in, const Eigen::Isometry3d& predicted,
                                    const Eigen::Vector3d& velocity_var_w, ScanResult& result) {
  // A weak translation is held in a corridor too (the IMU carries the
  // axis, the fuser is told): free, ICP followed the rings' pattern and
  // the walks stood still. Its pitch no longer goes wrong there since the
  // scans that pin the attitude level it (ImuFuserParams::
  // levelling_max_rotation_error_rad; docs/decisions/attitude-between-scans.md).
  // The prediction holds ICP where the scan pins the pose no better
  // (position_uncertainty.hpp); not where a clipped sensor made it a
  // guess, and not in a corridor (above) until its window is clear of
  // weak scans again: after a spell the fused velocity is whatever the
  // lost scans made it, and where the corridor half-pins its axis the
  // prior pulled the pose along it while its scans were published as good.
  result.prediction_prior = position_uncertainty_.enabled() && in.conditions.trajectory_measured &&
                            !unobserved_direction_.since_spell() &&
                            !clipped_since(in.trajectory, position_uncertainty_.updated_at_s());
  const Eigen::Matrix3d prior_information =
      result.prediction_prior
          ? position_uncertainty_.prior_information(in.t_start_s, params_.confidence.covariance_scale, velocity_var_w)
          : Eigen::Matrix3d::Zero();
  const IcpResult icp = icp_.align(registered_, map_, predicted, prior_information);
  result.registered = icp.matches_kept >= 6;
  result.converged = icp.converged;
  result.iterations = icp.iterations;
  result.inlier_ratio = icp.inlier_ratio;
  result.matched_ratio = icp.matched_ratio;
  result.residual_rms_m = icp.residual_rms_m;
  result.covariance = icp.covariance;
  result.degeneracy = icp.degeneracy;
  result.held_translation_w = icp.held_translation_w;
  result.timings.icp_matching_s = icp.matching_s;
  result.timings.icp_solve_s = icp.solve_s;
  result.correction_w = icp.T_wl.translation() - predicted.translation();
  result.rotation_from_prediction_rad =
      Eigen::AngleAxisd(predicted.rotation().transpose() * icp.T_wl.rotation()).angle();
  const auto beyond = [](double value, double limit) { return limit > 0 && value > limit; };
  if (result.registered && (beyond(result.correction_w.norm(), in.conditions.max_translation_m) ||
                            beyond(result.rotation_from_prediction_rad, in.conditions.max_rotation_rad))) {
    result.registered = false;
    result.rejected = true;
  }
  if (result.registered) result.T_wl = icp.T_wl;
}

// The registration's covariance, calibrated and fused with the prediction's
// where the prior held it; whether it jumped from the prediction; the
// unobserved direction's bookkeeping.
void ScanRegistration::estimate_uncertainty(const ScanInputs& in, const Eigen::Vector3d& velocity_var_w,
                                            ScanResult& result) {
  const double t_start = in.t_start_s;
  const double trace_sigma = std::sqrt(std::max(result.covariance.topLeftCorner<3, 3>().trace() / 3.0, 0.0));
  result.position_sigma_m = std::isfinite(trace_sigma) && !result.map_initialised
                                ? std::max(trace_sigma, params_.min_position_sigma_m)
                                : params_.min_position_sigma_m;
  // Calibrated (κ²): the ICP's own covariance is optimistic, most of all
  // along a weak direction, where the fuser must not take it as measured.
  if (!result.map_initialised && result.covariance.topLeftCorner<3, 3>().allFinite()) {
    const double kappa = params_.confidence.covariance_scale;
    result.position_var_w_m2 = kappa * kappa * result.covariance.topLeftCorner<3, 3>().diagonal();
  }
  // The scan that starts a map defines it: no registration error, only the floor.
  const Matrix6d icp_covariance = result.map_initialised ? Matrix6d::Zero() : result.covariance;
  const Matrix6d icp_published = published_covariance(icp_covariance, params_.confidence);
  // Only against a measured prediction: through clipping or without the IMU it is a guess.
  result.jumped = result.registered && !result.map_initialised && result.prediction_prior &&
                  position_uncertainty_.jumped(t_start, result.correction_w, icp_published.topLeftCorner<3, 3>());
  result.expected_error_icp_m = expected_position_error_m(icp_published);
  result.expected_rotation_error_icp_rad = expected_rotation_error_rad(icp_published);
  result.covariance_published = published_covariance(
      without_normal_noise(icp_covariance, result.degeneracy, params_.confidence.normal_noise_share),
      params_.confidence);
  if (result.registered && !result.map_initialised) {
    // Published unobserved from the spell's start until the window is clear
    // of weak scans, not only until it falls under half the bar: after a
    // spell a corridor's scans still half-pin its axis, claim 2 cm, and the
    // pose slides on.
    unobserved_direction_.add(result.degeneracy);
    result.direction_unobserved = unobserved_direction_.since_spell();
    result.unobserved_spell_ended = unobserved_direction_.spell_ended();
    if (result.direction_unobserved) unobserved_direction_.widen(result.covariance_published);
  }
  if (result.map_initialised) {
    position_uncertainty_.reset(t_start);
  } else if (!result.registered) {
    position_uncertainty_.predict_only(t_start, velocity_var_w);
  } else if (result.prediction_prior && !result.direction_unobserved) {
    // What a weak scan says along its weakest direction is the normals'
    // noise (the hold, icp.hpp): the prediction alone is known there, and
    // it grows scan after weak scan. Fused with the scan's few centimetres
    // instead, scans that had slid along a corridor with the prediction's
    // drift were published as good.
    Matrix6d measured = result.covariance_published;
    if (unobserved_direction_.weak(result.degeneracy)) {
      widen_along(measured, weakest_direction(result.degeneracy), params_.unobserved.sigma_m);
      result.weak_translation_predicted = mostly_translation(result.degeneracy.direction);
    }
    result.covariance_published = position_uncertainty_.fuse(t_start, measured, velocity_var_w);
  } else {
    // No prior, or the scan that declared a direction unobserved: published
    // as the scan says, widened there.
    position_uncertainty_.replace_with_scan(t_start, result.covariance_published, velocity_var_w);
  }
  result.expected_error_m = expected_position_error_m(result.covariance_published);
}

// Every beam_stride-th registered point casts a beam, the others on the next scans.
void ScanRegistration::remove_seen_through(const ScanInputs& in, ScanResult& result) {
  const std::size_t stride = params_.seen_through.beam_stride;
  const Eigen::Isometry3d to_scan_start = in.trajectory.pose_at(in.t_start_s).inverse();
  const Eigen::Matrix3d R_wl = result.T_wl.linear();
  std::size_t hint = 0;
  beams_.clear();
  for (std::size_t i = seen_through_scans_++ % stride; i < registered_.size(); i += stride) {
    MapBeam& beam = beams_.emplace_back();
    beam.origin_w = result.T_wl * (to_scan_start * in.trajectory.pose_at(registered_.times_s[i], hint)).translation();
    beam.end_w = result.T_wl * registered_.points[i];
    beam.end_normal_w =
        registered_.normal_valid[i] ? Eigen::Vector3d(R_wl * registered_.normals[i]) : Eigen::Vector3d::Zero();
  }
  returns_w_.resize(reading_.size());
  for (std::size_t i = 0; i < reading_.size(); ++i) returns_w_[i] = result.T_wl * reading_.points[i];
  result.map_points_seen_through = seen_through_.remove(map_, beams_, returns_w_);
}

// Only points with no map point within the minimum distance can go in; their
// normals and σ's are fitted now, their time counted in those stages.
void ScanRegistration::add_to_map(const ScanInputs& in, ScanResult& result) {
  StageTimings& timing = result.timings;
  const std::size_t candidates = map_.find_insert_candidates(reading_.points, result.T_wl, candidate_indices_);
  lap(timing.map_update_s);
  fit_normals(candidate_indices_);
  lap(timing.normals_s);
  gather(candidate_indices_, map_candidates_);
  if (!weighs_whole_scan()) weigh(in, map_candidates_);
  lap(timing.weights_s);
  result.map_insert = map_.insert(map_candidates_, result.T_wl);
  result.map_insert.rejected_too_close += reading_.size() - candidates;
  map_.remove_far_from(result.T_wl.translation());
}

}  // namespace tumble
