#include "core/odometry.hpp"

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
  auto fail = [](const std::string& what) { throw std::invalid_argument("OdometryParams: " + what); };
  if (p.max_pending_scans < 1) fail("max_pending_scans must be >= 1");
  if (p.weights.map_max_sigma_m != p.map.max_sigma_s_m)
    fail("weights.map_max_sigma_m (" + std::to_string(p.weights.map_max_sigma_m) + ") and map.max_sigma_s_m (" +
         std::to_string(p.map.max_sigma_s_m) + ") must be equal");
  if (!(p.min_position_sigma_m > 0)) fail("min_position_sigma_m must be > 0");
  return p;
}

}  // namespace

Odometry::Odometry(const OdometryParams& params, Clock clock)
    : params_(checked(params)),
      clock_(std::move(clock)),
      fuser_(params.fuser),
      downsampler_(params.voxel_size_m),
      normals_(params.reading_normals),
      icp_(icp_params_for(params)),
      map_(params.map),
      pending_(params.max_pending_scans) {}

std::size_t Odometry::add_imu(const ImuSample& sample) {
  fuser_.add_imu(sample);
  if (!fuser_.initialized()) return 0;
  if (on_pose_ && !fuser_.trajectory().empty()) on_pose_(fuser_.trajectory().back());
  return process_ready_scans();
}

std::size_t Odometry::add_scan(const Scan& scan) {
  ++stats_.scans_received;
  if (scan.points.empty()) {
    ++stats_.scans_too_small;
    return 0;
  }
  if (!params_.wait_for_imu) {
    if (!fuser_.initialized() || fuser_.trajectory().empty()) {
      ++stats_.scans_before_init;
      return 0;
    }
    return process(scan) ? 1 : 0;
  }
  if (pending_count_ == pending_.size()) {  // drop the oldest
    pending_head_ = (pending_head_ + 1) % pending_.size();
    --pending_count_;
    ++stats_.scans_dropped_pending;
  }
  Scan& slot = pending_[(pending_head_ + pending_count_) % pending_.size()];
  slot.index = scan.index;
  slot.missing_packets = scan.missing_packets;
  slot.points.assign(scan.points.begin(), scan.points.end());
  ++pending_count_;
  return process_ready_scans();
}

bool Odometry::covered_by_imu(const Scan& scan) const {
  return fuser_.initialized() && !fuser_.trajectory().empty() &&
         fuser_.trajectory().t_end_s() >= scan.points.back().t_s;
}

std::size_t Odometry::process_ready_scans() {
  std::size_t processed = 0;
  while (pending_count_ > 0) {
    const Scan& scan = pending_[pending_head_];
    if (!fuser_.initialized()) {
      // The fuser is still in its static window: scans that end before its
      // trajectory can start will never be covered.
      ++stats_.scans_before_init;
    } else if (covered_by_imu(scan)) {
      if (scan.points.front().t_s < fuser_.trajectory().t_begin_s()) {
        ++stats_.scans_before_init;
      } else if (process(scan)) {
        ++processed;
      }
    } else {
      break;
    }
    pending_head_ = (pending_head_ + 1) % pending_.size();
    --pending_count_;
  }
  return processed;
}

Eigen::Vector3d Odometry::velocity_at(double t_s) const {
  const Trajectory& traj = fuser_.trajectory();
  std::size_t lo = 0, hi = traj.size() - 1;
  if (t_s <= traj[lo].t_s) return traj[lo].v_w;
  if (t_s >= traj[hi].t_s) return traj[hi].v_w;
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    (traj[mid].t_s <= t_s ? lo : hi) = mid;
  }
  const double a = (t_s - traj[lo].t_s) / (traj[hi].t_s - traj[lo].t_s);
  return (1 - a) * traj[lo].v_w + a * traj[hi].v_w;
}

bool Odometry::process(const Scan& scan) {
  const double t_start = scan.points.front().t_s;
  if (t_start <= last_scan_start_s_) {
    ++stats_.scans_out_of_order;
    return false;
  }
  last_scan_start_s_ = t_start;
  ScanResult result;
  result.scan_index = scan.index;
  result.t_scan_start_s = t_start;
  result.t_scan_end_s = scan.points.back().t_s;
  result.points_in = scan.points.size();
  StageTimings& timing = result.timings;
  timing.measured = static_cast<bool>(clock_);
  const Trajectory& trajectory = fuser_.trajectory();
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
  if (reading_.size() < params_.min_scan_points) {
    ++stats_.scans_too_small;
    return false;
  }

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
  Eigen::Isometry3d T_wl = predicted;
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
    if (result.registered) T_wl = icp.T_wl;
    if (!result.registered) ++stats_.registrations_failed;
    if (icp.degeneracy.degenerate) ++stats_.registrations_degenerate;
  }
  lap(timing.registration_s);

  if (result.registered) {
    const double trace_sigma = std::sqrt(std::max(result.covariance.topLeftCorner<3, 3>().trace() / 3.0, 0.0));
    const double sigma =
        std::isfinite(trace_sigma) && !result.map_initialised ? std::max(trace_sigma, params_.min_position_sigma_m)
                                                              : params_.min_position_sigma_m;
    fuser_.correct_with_registered_pose(t_start, T_wl, sigma);
  }
  result.T_wl = T_wl;
  result.v_w = velocity_at(t_start);
  lap(timing.fuser_correction_s);

  if (result.registered) {
    result.map_insert = map_.insert(reading_, T_wl);
    map_.remove_far_from(T_wl.translation());
  }
  result.map_points = map_.size();
  lap(timing.map_update_s);
  timing.total_s = mark - clock_start;

  ++stats_.scans_processed;
  last_result_ = result;
  if (on_scan_) on_scan_(result);
  return true;
}

}  // namespace tumble
