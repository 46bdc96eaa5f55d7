// tumbled's configuration: one typed struct whose defaults are the paper's
// values and equal config/tumbled.yaml (a test loads the shipped file and
// compares), a strict YAML loader, and a printer whose output loads back to
// the same struct.
//
// Precedence: compiled defaults < the YAML file < command-line overrides.
// Keys missing from the file keep their defaults. Unknown keys, duplicate
// keys, wrong types, out-of-range values and inconsistent pairs throw
// ConfigError with ONE line naming the key path and what is allowed, e.g.
//   registration.voxel_size_m: 0 is out of range (0.005..1)
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/scan_line_normals.hpp"
#include "daemon/records.hpp"

namespace tumble::daemon {

struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class LidarClock { Synced, Free };
enum class AttitudeSource { Madgwick, Device };
enum class LogLevel { Trace, Debug, Info, Warn, Error, Critical, Off };

struct LidarConfig {
  std::string bind_address = "0.0.0.0";
  int msop_port = 6699;
  int difop_port = 7788;
  std::string source_ip;  // empty: the first sender of a well-formed MSOP datagram, for the whole run
  double split_azimuth_deg = 0.0;
  double min_scan_coverage = 0.9;  // fraction of a turn; shorter scans are skipped (and counted)
  double min_range_m = 0.4;
  double max_range_m = 200.0;
  LidarClock clock = LidarClock::Free;
  std::vector<double> vertical_angles_deg;  // empty: from DIFOP; else 16 values, laser 0..15
  bool follow_difop_changes = false;  // false: the first calibrated DIFOP's settings hold for the run
  int receive_buffer_bytes = 4 << 20;  // per socket; the kernel caps it at net.core.rmem_max
  bool operator==(const LidarConfig&) const = default;
};

// T_LI: maps IMU-frame coordinates into the lidar frame. Exactly one rotation form is set.
struct ExtrinsicConfig {
  std::array<double, 3> translation_m{0.0, 0.0, 0.0};
  std::optional<std::array<double, 3>> rotation_rpy_deg = std::array<double, 3>{0.0, 0.0, 0.0};
  std::optional<std::array<double, 4>> rotation_quaternion_wxyz;
  bool operator==(const ExtrinsicConfig&) const = default;
};

struct ImuConfig {
  std::string device = "/dev/ttyUSB0";
  int baud = 115200;
  bool configure = true;
  int rate_hz = 100;
  double imu_time_offset_s = 0.0;
  ExtrinsicConfig extrinsic_T_LI;
  double gyro_noise_density_deg_s_sqrt_hz = 0.03;
  double accel_noise_density_ug_sqrt_hz = 60.0;
  // The device's range per axis (MTi-30 G4, A8): samples beyond 1.5 times it are rejected.
  double gyro_range_deg_s = 450.0;
  double accel_range_m_s2 = 200.0;
  bool operator==(const ImuConfig&) const = default;
};

struct FuserConfig {
  double madgwick_beta = 0.1;
  double accel_gate_m_s2 = 2.0;
  double accel_correction_after_s = 0.5;
  double levelling_max_expected_error_m = 0.024;
  double levelling_max_rotation_error_deg = 0.15;
  double init_static_s = 1.0;
  double rest_static_s = 0.5;
  double max_speed_m_s = 6.0;
  double max_speed_at_rest_m_s = 0.3;
  AttitudeSource attitude_source = AttitudeSource::Madgwick;
  bool operator==(const FuserConfig&) const = default;
};

struct RegistrationConfig {
  WeightModel model = WeightModel::GVTW;
  bool deskew = true;
  double voxel_size_m = 0.05;
  double icp_voxel_size_m = 0.2;
  int normal_k_map = 20;
  int normal_k_reading = 15;
  ReadingNormalSource reading_normals = ReadingNormalSource::kScanLines;
  int scan_line_points_each_side = 5;
  int scan_line_rings_each_side = 2;
  double max_match_distance_m = 1.0;
  int match_k = 1;
  double frmsd_min_ratio = 0.5;
  double frmsd_max_ratio = 0.7;
  double frmsd_lambda = 2.35;
  int max_iterations = 40;
  double convergence_translation_m = 0.01;
  double convergence_rotation_rad = 0.001;
  int convergence_window_iterations = 2;
  double unobserved_min_eigenvalue = 0.002;
  int unobserved_window_scans = 20;
  double unobserved_fraction = 0.9;
  double unobserved_sigma_m = 1.0;
  bool hold_weak_translation = true;
  double prediction_sigma_m = 0.02;
  double jump_sigmas = 5.0;
  double sigma_n_floor_m = 0.02;
  double sigma_n_beam_rad = 0.0015;
  double tw_c1_m_s = 0.25;
  double vtw_c2 = 2.0;
  double gvtw_c3 = 4.0;
  double saw_c_r = 0.1;
  double lognormal_beta = 1.1;
  double lognormal_kappa_m_s = 1.9;
  double lognormal_lambda = 0.222;
  double cubic_phi_rad_s = 16.0;
  double no_deskew_sigma_v_ratio = 0.14;
  double no_deskew_sigma_omega_ratio = 0.72;
  double corner_point_uncertainty_m = 0.0;
  bool operator==(const RegistrationConfig&) const = default;
};

struct MapConfig {
  double radius_m = 50.0;
  double min_point_distance_m = 0.05;
  double max_sigma_m = 1.0;
  double voxel_size_m = 0.5;
  int points_per_voxel = 100;
  bool remove_seen_through = true;
  double seen_through_beam_radius_m = 0.05;
  double seen_through_margin_m = 0.5;
  double seen_through_max_range_m = 30.0;
  double seen_through_max_expected_error_m = 0.024;
  int seen_through_beam_stride = 2;
  bool operator==(const MapConfig&) const = default;
};

struct LcmConfig {
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  std::string channel_prefix = "TUMBLE_";
  bool publish_scan = false;
  double publish_map_period_s = 0.0;  // data time between local map messages; 0: none
  bool operator==(const LcmConfig&) const = default;
};

struct HealthConfig {
  double sensor_timeout_s = 0.2;
  double degraded_to_lost_s = 3.0;
  double lidar_silent_to_lost_s = 1.0;
  double scan_timeout_s = 0.5;  // lidar points but no scan completed this long: stale
  int good_scans_to_recover = 5;
  double min_matched_ratio = 0.25;
  double min_matched_ratio_spin_clipped = 0.3;
  int spin_clipped_scans_to_settle = 3;
  double min_degeneracy = 0.0005;
  double max_expected_error_m = 0.04;
  double second_lidar_rate_hz = 375.0;  // foreign datagrams/s to the MSOP port that are a second lidar
  bool operator==(const HealthConfig&) const = default;
};

struct DaemonSection {
  int imu_ring_capacity = 1024;
  int lidar_ring_capacity = 1024;
  int correction_ring_capacity = 16;
  int odometry_ring_capacity = 1024;
  int registration_ring_capacity = 64;
  int scan_report_ring_capacity = 64;
  int trajectory_buffer_capacity = 8192;
  double trajectory_wait_s = 0.2;
  int realtime_priority = 0;
  int registration_nice = 0;
  int registration_threads = 2;
  LogLevel log_level = LogLevel::Info;
  double status_period_s = 1.0;
  double checkpoint_period_s = 2.0;  // output files are made durable this often: a power cut loses at most this
  HealthConfig health;
  bool operator==(const DaemonSection&) const = default;
};

struct RecordConfig {
  std::string dir;  // empty: do not record
  int max_segment_mib = 1024;  // a segment (one directory) is closed after this many MiB of both files
  double max_segment_s = 600.0;  // or after this long
  int min_free_mib = 1024;  // recording pauses below this much free space on record.dir's file system
  bool operator==(const RecordConfig&) const = default;
};

struct DaemonConfig {
  LidarConfig lidar;
  ImuConfig imu;
  FuserConfig fuser;
  RegistrationConfig registration;
  MapConfig map;
  LcmConfig lcm;
  DaemonSection daemon;
  RecordConfig record;
  bool operator==(const DaemonConfig&) const = default;
};

// A value given on the command line for one key, e.g. {"registration.model", "NM"}.
struct ConfigOverride {
  std::string key;
  std::string value;
};

// Parses YAML text (source_name only names it in messages) and applies overrides.
DaemonConfig load_config(std::string_view yaml_text, std::string_view source_name,
                         std::span<const ConfigOverride> overrides = {});
// Reads and parses a file; a missing or unreadable file is a ConfigError.
DaemonConfig load_config_file(const std::string& path, std::span<const ConfigOverride> overrides = {});
// The compiled defaults with overrides applied (no file).
DaemonConfig default_config(std::span<const ConfigOverride> overrides = {});

// The whole configuration as YAML; load_config(to_yaml(c)) == c.
std::string to_yaml(const DaemonConfig& config);

// Every key's dotted path (e.g. "imu.extrinsic_T_LI.translation_m"), in file
// order; both rotation forms of the extrinsic are listed.
std::vector<std::string> config_keys();

// Throws ConfigError when a value set in code violates the same rules the loader checks.
void validate(const DaemonConfig& config);

std::string_view to_string(WeightModel model);
std::string_view to_string(LogLevel level);

// T_LI as a rigid transform (rpy: R = Rz(yaw) * Ry(pitch) * Rx(roll)).
Eigen::Isometry3d extrinsic_T_LI(const ExtrinsicConfig& extrinsic);

}  // namespace tumble::daemon
