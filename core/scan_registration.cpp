#include "core/scan_registration.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/deskew.hpp"

namespace tumble {

namespace {

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
  if (p.max_pending_scans < 1) fail("max_pending_scans must be >= 1");
  if (p.weights.map_max_sigma_m != p.map.max_sigma_s_m)
    fail("weights.map_max_sigma_m (" + std::to_string(p.weights.map_max_sigma_m) + ") and map.max_sigma_s_m (" +
         std::to_string(p.map.max_sigma_s_m) + ") must be equal");
  if (!(p.min_position_sigma_m > 0)) fail("min_position_sigma_m must be > 0");
}

ScanRegistration::ScanRegistration(const OdometryParams& params, Clock clock)
    : params_(checked(params)),
      clock_(std::move(clock)),
      downsampler_(params.voxel_size_m),
      normals_(params.reading_normals),
      icp_(icp_params_for(params)),
      map_(params.map) {}

void ScanRegistration::reset() {
  map_.clear();
  last_scan_start_s_ = -1e300;
}

ScanOutcome ScanRegistration::process(const Scan& scan, const Trajectory& trajectory, ScanResult& result) {
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
  double mark = clock_start;
  auto lap = [&](double& stage) {
    const double t = now();
    stage = t - mark;
    mark = t;
  };

  // De-skew into the lidar frame at the scan's first point.
  const std::size_t n = scan.points.size();
  raw_.resize(n);
  deskew_scan(scan, trajectory, params_.deskew, raw_.points);
  for (std::size_t i = 0; i < n; ++i) {
    raw_.times_s[i] = scan.points[i].t_s;
    raw_.rings[i] = scan.points[i].laser;
  }
  lap(timing.deskew_s);

  downsampler_.apply(raw_, reading_);
  result.points_downsampled = reading_.size();
  lap(timing.downsample_s);
  if (reading_.size() < params_.min_scan_points) return ScanOutcome::TooSmall;

  normals_.estimate(reading_, Eigen::Vector3d::Zero());
  lap(timing.normals_s);

  PointWeightInput input;
  input.points_l = reading_.points;
  input.times_s = reading_.times_s;
  input.normals = reading_.normals;
  input.curvatures = reading_.curvatures;
  input.rings = reading_.rings;
  input.t_scan_start_s = t_start;
  input.deskewed = params_.deskew;
  compute_point_weights(params_.weights, trajectory, input,
                        PointWeightOutput{reading_.sigma_n_m, reading_.sigma_s_m, reading_.weights}, weight_workspace_);
  lap(timing.weights_s);

  const Eigen::Isometry3d predicted = trajectory.pose_at(t_start);
  result.T_wl = predicted;
  if (map_.empty()) {
    result.map_initialised = true;
    result.registered = true;
  } else {
    const IcpResult icp = icp_.align(reading_, map_, predicted);
    result.registered = icp.matches_kept >= 6;
    result.converged = icp.converged;
    result.iterations = icp.iterations;
    result.inlier_ratio = icp.inlier_ratio;
    result.residual_rms_m = icp.residual_rms_m;
    result.covariance = icp.covariance;
    result.degeneracy = icp.degeneracy;
    if (result.registered) result.T_wl = icp.T_wl;
  }
  const double trace_sigma = std::sqrt(std::max(result.covariance.topLeftCorner<3, 3>().trace() / 3.0, 0.0));
  result.position_sigma_m = std::isfinite(trace_sigma) && !result.map_initialised
                                ? std::max(trace_sigma, params_.min_position_sigma_m)
                                : params_.min_position_sigma_m;
  lap(timing.registration_s);

  if (result.registered) {
    result.map_insert = map_.insert(reading_, result.T_wl);
    map_.remove_far_from(result.T_wl.translation());
  }
  result.map_points = map_.size();
  lap(timing.map_update_s);
  timing.total_s = mark - clock_start;
  return ScanOutcome::Registered;
}

}  // namespace tumble
