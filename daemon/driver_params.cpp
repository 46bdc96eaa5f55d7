#include "daemon/driver_params.hpp"

#include <algorithm>

#include "core/angles.hpp"
#include "core/types.hpp"

namespace tumble::daemon {

OdometryParams odometry_params(const DaemonConfig& config) {
  const RegistrationConfig& r = config.registration;
  OdometryParams p;
  p.deskew = r.deskew;
  p.voxel_size_m = r.voxel_size_m;
  p.registration_voxel_size_m = r.icp_voxel_size_m;
  p.reading_normals.k = r.normal_k_reading;
  p.reading_normal_source = r.reading_normals;
  p.scan_line_window.points_each_side = r.scan_line_points_each_side;
  p.scan_line_window.rings_each_side = r.scan_line_rings_each_side;

  p.map.normals.k = r.normal_k_map;
  p.map.radius_m = config.map.radius_m;
  p.map.min_point_distance_m = config.map.min_point_distance_m;
  p.map.max_sigma_s_m = config.map.max_sigma_m;
  p.map.voxel_size_m = config.map.voxel_size_m;
  p.map.max_points_per_voxel = static_cast<std::size_t>(config.map.points_per_voxel);
  p.seen_through.enabled = config.map.remove_seen_through;
  p.seen_through.beam_radius_m = config.map.seen_through_beam_radius_m;
  p.seen_through.margin_m = config.map.seen_through_margin_m;
  p.seen_through.max_range_m = config.map.seen_through_max_range_m;
  p.seen_through.max_expected_error_m = config.map.seen_through_max_expected_error_m;
  p.seen_through.beam_stride = static_cast<std::size_t>(config.map.seen_through_beam_stride);

  p.icp.max_match_distance_m = r.max_match_distance_m;
  p.icp.match_k = r.match_k;
  p.icp.frmsd_r_min = r.frmsd_min_ratio;
  p.icp.frmsd_r_max = r.frmsd_max_ratio;
  p.icp.frmsd_lambda = r.frmsd_lambda;
  p.icp.max_iterations = r.max_iterations;
  p.icp.averaged_translation_m = r.convergence_translation_m;
  p.icp.averaged_rotation_rad = r.convergence_rotation_rad;
  p.icp.averaged_window = r.convergence_window_iterations;
  p.unobserved.weak_min_eigenvalue = r.unobserved_min_eigenvalue;
  p.unobserved.window_scans = static_cast<std::size_t>(r.unobserved_window_scans);
  p.unobserved.enter_fraction = r.unobserved_fraction;
  p.unobserved.sigma_m = r.unobserved_sigma_m;
  p.icp.hold_weak_translation_share = r.hold_weak_translation ? r.unobserved_min_eigenvalue : 0.0;
  p.fuser.unmeasured_position_sigma_m = r.unobserved_sigma_m;
  p.position.prediction_sigma_m = r.prediction_sigma_m;
  p.position.jump_sigmas = r.jump_sigmas;

  p.weights.model = r.model;
  p.weights.tw_c1_m_s = r.tw_c1_m_s;
  p.weights.vtw_c2 = r.vtw_c2;
  p.weights.gvtw_c3 = r.gvtw_c3;
  p.weights.saw_reference_curvature = r.saw_c_r;
  p.weights.sensor_noise_min_m = r.sigma_n_floor_m;
  p.weights.sensor_noise_rad = r.sigma_n_beam_rad;
  p.weights.corner_point_uncertainty_m = r.corner_point_uncertainty_m;
  p.weights.map_max_sigma_m = config.map.max_sigma_m;

  SpeedUncertaintyParams& s = p.fuser.speed_uncertainty;
  s.lognormal_shape_beta = r.lognormal_beta;
  s.lognormal_scale_kappa_m_s = r.lognormal_kappa_m_s;
  s.lognormal_gain_lambda = r.lognormal_lambda;
  s.cubic_scale_phi_rad_s = r.cubic_phi_rad_s;
  s.raw_linear_gain = r.no_deskew_sigma_v_ratio;
  s.raw_angular_gain = r.no_deskew_sigma_omega_ratio;

  p.fuser.T_li = extrinsic_T_LI(config.imu.extrinsic_T_LI);
  p.fuser.static_duration_s = config.fuser.init_static_s;
  p.fuser.rest_duration_s = config.fuser.rest_static_s;
  p.fuser.max_speed_m_s = config.fuser.max_speed_m_s;
  p.fuser.max_speed_at_rest_m_s = config.fuser.max_speed_at_rest_m_s;
  p.fuser.madgwick.beta = config.fuser.madgwick_beta;
  p.fuser.madgwick.accel_gate_m_s2 = config.fuser.accel_gate_m_s2;
  p.fuser.accel_correction_after_s = config.fuser.accel_correction_after_s;
  p.fuser.levelling_max_expected_error_m = config.fuser.levelling_max_expected_error_m;
  p.fuser.levelling_max_rotation_error_rad = config.fuser.levelling_max_rotation_error_deg * kDegToRad;
  p.fuser.attitude_from_device = config.fuser.attitude_source == AttitudeSource::Device;
  p.fuser.accel_noise_density_m_s2_sqrt_hz = config.imu.accel_noise_density_ug_sqrt_hz * 1e-6 * kStandardGravity_m_s2;
  // The re-propagation history must span a scan and the registration's lag
  // behind the IMU: a few seconds at the configured rate.
  const auto seconds_of_samples = static_cast<std::size_t>(4.0 * config.imu.rate_hz);
  p.fuser.history_capacity = std::max(p.fuser.history_capacity, seconds_of_samples);
  p.fuser.trajectory_capacity = std::max(p.fuser.trajectory_capacity, seconds_of_samples);
  return p;
}

rs16::DecoderConfig lidar_decoder_config(const LidarConfig& lidar) {
  rs16::DecoderConfig d;
  d.min_range_m = lidar.min_range_m;
  d.max_range_m = lidar.max_range_m;
  d.clock = lidar.clock == LidarClock::Synced ? rs16::ClockMode::Synced : rs16::ClockMode::Free;
  d.follow_difop_changes = lidar.follow_difop_changes;
  if (!lidar.vertical_angles_deg.empty()) {
    std::array<double, rs16::kLasers> angles{};
    std::copy_n(lidar.vertical_angles_deg.begin(), rs16::kLasers, angles.begin());
    d.vertical_angles_deg = angles;
  }
  return d;
}

rs16::SourceConfig lidar_source_config(const LidarConfig& lidar) {
  rs16::SourceConfig s;
  s.msop_port = static_cast<std::uint16_t>(lidar.msop_port);
  s.difop_port = static_cast<std::uint16_t>(lidar.difop_port);
  if (!lidar.source_ip.empty()) s.source_ip = rs16::parse_ipv4(lidar.source_ip);
  return s;
}

rs16::ScanAssemblerConfig scan_assembler_config(const LidarConfig& lidar) {
  return rs16::ScanAssemblerConfig{.split_azimuth_deg = lidar.split_azimuth_deg,
                                   .min_scan_coverage = lidar.min_scan_coverage};
}

mti::MtiStreamOptions imu_stream_options(const ImuConfig& imu) {
  mti::MtiStreamOptions o;
  o.imu_rate_hz = imu.rate_hz;
  o.baud = static_cast<std::uint32_t>(imu.baud);
  o.imu_time_offset_s = imu.imu_time_offset_s;
  return o;
}

ImuLimits imu_limits(const ImuConfig& imu) {
  return ImuLimits{imu.gyro_range_deg_s * kDegToRad, imu.accel_range_m_s2};
}

mti::SerialSourceOptions serial_source_options(const ImuConfig& imu) {
  mti::SerialSourceOptions o;
  o.device = imu.device;
  o.configurator.configure = imu.configure;
  o.configurator.imu_rate_hz = static_cast<std::uint16_t>(imu.rate_hz);
  o.configurator.baud = static_cast<std::uint32_t>(imu.baud);
  o.imu_time_offset_s = imu.imu_time_offset_s;
  return o;
}

}  // namespace tumble::daemon
