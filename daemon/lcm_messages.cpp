#include "daemon/lcm_messages.hpp"

#include <algorithm>
#include <cmath>

#include "daemon/config.hpp"

namespace tumble::daemon {

std::int64_t to_utime(double t_s) { return std::llround(t_s * 1e6); }

void to_lcm(const TrajectoryRecord& s, std::int64_t seq, float latency_ms, tumble::odometry_t& out) {
  out.utime = to_utime(s.t_s);
  out.seq = seq;
  out.latency_ms = latency_ms;
  std::copy(s.p_w_m.begin(), s.p_w_m.end(), out.position_m);
  std::copy(s.q_wl_wxyz.begin(), s.q_wl_wxyz.end(), out.orientation);
  std::copy(s.v_w_m_s.begin(), s.v_w_m_s.end(), out.velocity_m_s);
  std::copy(s.omega_l_rad_s.begin(), s.omega_l_rad_s.end(), out.angular_velocity_rad_s);
  std::copy(s.position_var_m2.begin(), s.position_var_m2.end(), out.position_var_m2);
  std::copy(s.velocity_var_m2_s2.begin(), s.velocity_var_m2_s2.end(), out.velocity_var_m2_s2);
  // A trajectory sample exists only once the fuser is initialised.
  std::int32_t flags = tumble::odometry_t::FLAG_INITIALISED;
  if (s.lidar_corrected) flags |= tumble::odometry_t::FLAG_LIDAR_CORRECTED;
  if (s.gyro_saturated_axes != 0) flags |= tumble::odometry_t::FLAG_GYRO_SATURATED;
  if (s.accel_saturated_axes != 0) flags |= tumble::odometry_t::FLAG_ACCEL_SATURATED;
  if (s.attitude_from_device) flags |= tumble::odometry_t::FLAG_ATTITUDE_FROM_DEVICE;
  if (s.imu_bridged) flags |= tumble::odometry_t::FLAG_IMU_BRIDGED;
  if (s.awaiting_rest) flags |= tumble::odometry_t::FLAG_AWAITING_REST;
  out.flags = flags;
  out.resets = s.resets;
}

void to_lcm(const RegistrationRecord& r, const std::vector<std::string>& stage_names, float latency_ms,
            tumble::registration_t& out) {
  out.utime = to_utime(r.t_s);
  out.scan_index = r.scan_index;
  std::copy(r.position_m.begin(), r.position_m.end(), out.position_m);
  std::copy(r.orientation_wxyz.begin(), r.orientation_wxyz.end(), out.orientation);
  std::copy(r.velocity_m_s.begin(), r.velocity_m_s.end(), out.velocity_m_s);
  std::copy(r.covariance.begin(), r.covariance.end(), out.covariance);
  out.iterations = r.iterations;
  out.registered = r.registered;
  out.converged = r.converged;
  out.inlier_ratio = r.inlier_ratio;
  out.residual_m = r.residual_m;
  out.degeneracy = r.degeneracy;
  out.model = to_string(r.model);
  out.deskew = r.deskew;
  out.points_in = r.points_in;
  out.points_used = r.points_used;
  out.sigma_s_median_m = r.sigma_s_median_m;
  out.sigma_s_max_m = r.sigma_s_max_m;
  out.latency_ms = latency_ms;
  out.resets = r.resets;
  out.imu_bridged = r.imu_bridged;
  out.spin_rate_unmeasured = r.spin_rate_unmeasured;
  out.map_deferred = r.map_deferred;
  out.direction_unobserved = r.direction_unobserved;
  out.expected_error_icp_m = r.expected_error_icp_m;
  out.jumped = r.jumped;
  out.awaiting_rest = r.awaiting_rest;
  out.expected_error_m = r.expected_error_m;
  const std::size_t stages = std::min<std::size_t>({r.num_stages, stage_names.size(), RegistrationRecord::kMaxStages});
  out.num_stages = static_cast<std::int16_t>(stages);
  out.stage_name.resize(stages);
  out.stage_ms.resize(stages);
  for (std::size_t i = 0; i < stages; ++i) {
    out.stage_name[i] = stage_names[i];
    out.stage_ms[i] = r.stage_ms[i];
  }
}

}  // namespace tumble::daemon
