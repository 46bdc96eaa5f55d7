#include "tools/sim/scenario.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <numbers>
#include <sstream>
#include <tuple>

#include "core/angles.hpp"
#include "tools/sim/yaml_fields.hpp"

namespace tumble::sim {
namespace {

constexpr const char* kDefaultEpoch = "2021-05-26T12:00:00Z";

// "YYYY-MM-DDTHH:MM:SS[.fraction]Z" as nanoseconds since the Unix epoch.
std::optional<std::int64_t> parse_utc(const std::string& text) {
  std::tm tm{};
  int consumed = 0;
  if (std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%n", &tm.tm_year, &tm.tm_mon, &tm.tm_mday, &tm.tm_hour,
                  &tm.tm_min, &tm.tm_sec, &consumed) != 6) {
    return std::nullopt;
  }
  std::int64_t fraction_ns = 0;
  std::size_t i = static_cast<std::size_t>(consumed);
  if (i < text.size() && text[i] == '.') {
    std::int64_t scale = 100'000'000;
    for (++i; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i, scale /= 10) {
      fraction_ns += (text[i] - '0') * scale;
    }
  }
  if (i + 1 != text.size() || text[i] != 'Z') return std::nullopt;
  if (tm.tm_year < 2000 || tm.tm_year > 2200 || tm.tm_mon < 1 || tm.tm_mon > 12) return std::nullopt;
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  return static_cast<std::int64_t>(timegm(&tm)) * 1'000'000'000 + fraction_ns;
}

mti::NumberFormat parse_number_format(const YamlPath& at, const std::string& text) {
  if (text == "float32") return mti::NumberFormat::Float32;
  if (text == "fp1220") return mti::NumberFormat::Fp1220;
  if (text == "fp1632") return mti::NumberFormat::Fp1632;
  if (text == "float64") return mti::NumberFormat::Float64;
  at.fail("must be float32, fp1220, fp1632 or float64, got '" + text + "'");
}

// A name (no slash, no extension) means <kind dir>/<name>.yaml; anything else
// is a path, relative to the scenario's folder.
std::filesystem::path resolve_ref(const std::string& ref, const std::string& kind, const std::filesystem::path& base) {
  const std::filesystem::path p(ref);
  if (ref.find('/') == std::string::npos && !p.has_extension()) return sim_data_dir(kind) / (ref + ".yaml");
  return p.is_absolute() ? p : base / p;
}

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

double read_in(const YAML::Node& m, const YamlPath& at, std::string_view key, double fallback, double lo, double hi) {
  const double v = read_double(m, at, key, fallback);
  if (v < lo || v > hi) at.key(key).fail("must be in [" + number_text(lo) + ", " + number_text(hi) + "], got " + number_text(v));
  return v;
}

int read_int_in(const YAML::Node& m, const YamlPath& at, std::string_view key, int fallback, int lo, int hi) {
  const int v = read_count(m, at, key, fallback);
  if (v < lo || v > hi) at.key(key).fail("must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(v));
  return v;
}

std::optional<double> read_optional_in(const YAML::Node& m, const YamlPath& at, std::string_view key, double lo, double hi) {
  if (!has_key(m, key)) return std::nullopt;
  return read_in(m, at, key, 0.0, lo, hi);
}

// An absent section reads as an empty map (every key at its default).
YAML::Node section(const YAML::Node& m, std::string_view key) {
  const YAML::Node n = m[std::string(key)];
  return n && !n.IsNull() ? n : YAML::Node(YAML::NodeType::Map);
}

Eigen::Isometry3d read_pose(const YAML::Node& pose, const YamlPath& at) {
  check_keys(pose, at, {"translation_m", "rpy_deg"});
  return pose_from_xyz_rpy_deg(read_vec3(pose, at, "translation_m", Eigen::Vector3d::Zero()),
                               read_vec3(pose, at, "rpy_deg", Eigen::Vector3d::Zero()));
}

// The section's presence turns the bars on; `cage_bars: {}` is the bench's cage.
void read_cage_bars(const YAML::Node& m, const YamlPath& at, CageBars& bars) {
  check_keys(m, at, {"count", "cage_radius_m", "bar_radius_m", "length_m", "axis", "centre_m", "reflectivity"});
  bars.enabled = true;
  bars.count = read_int_in(m, at, "count", bars.count, 1, 64);
  bars.cage_radius_m = read_in(m, at, "cage_radius_m", bars.cage_radius_m, 0.05, 5.0);
  bars.bar_radius_m = read_in(m, at, "bar_radius_m", bars.bar_radius_m, 0.001, 0.2);
  if (bars.bar_radius_m >= bars.cage_radius_m) at.key("bar_radius_m").fail("must be below cage_radius_m");
  bars.length_m = read_in(m, at, "length_m", bars.length_m, 0.01, 10.0);
  bars.axis_l = read_vec3(m, at, "axis", bars.axis_l);
  if (!(bars.axis_l.norm() > 1e-9)) at.key("axis").fail("must be a nonzero vector");
  bars.centre_l = read_vec3(m, at, "centre_m", bars.centre_l);
  bars.reflectivity = read_in(m, at, "reflectivity", bars.reflectivity, 0.0, 1.0);
}

void read_lidar(const YAML::Node& m, const YamlPath& at, Scenario& s) {
  check_keys(m, at,
             {"rpm", "range_noise_m", "min_range_m", "max_range_m", "dropout_probability", "incidence_falloff_exponent",
              "vertical_offset_sigma_deg", "temperature_c", "unit_seed", "msop_port", "difop_port", "network_latency_s",
              "network_jitter_s", "difop_period_s", "difop_phase_s", "range_offset_error", "range_offset_sigma_m",
              "intensity_range_bias", "intensity_range_walk_m", "dark_surface_dropout",
              "range_at_reference_reflectivity_m", "reference_reflectivity", "cage_bars", "mixed_pixels",
              "beam_divergence_horizontal_mrad", "beam_divergence_vertical_mrad", "mixed_pixel_max_gap_m"});
  LidarConfig& c = s.lidar;
  LidarLinkConfig& link = s.lidar_link;
  c.rpm = read_int_in(m, at, "rpm", c.rpm, 300, 1200);
  if (c.rpm != 300 && c.rpm != 600 && c.rpm != 1200) at.key("rpm").fail("must be 300, 600 or 1200");
  c.range_noise_m = read_in(m, at, "range_noise_m", c.range_noise_m, 0.0, 1.0);
  c.min_range_m = read_in(m, at, "min_range_m", c.min_range_m, 0.0, 10.0);
  c.max_range_m = read_in(m, at, "max_range_m", c.max_range_m, 1.0, 300.0);
  if (c.min_range_m >= c.max_range_m) at.key("min_range_m").fail("must be below max_range_m");
  c.dropout_probability = read_in(m, at, "dropout_probability", c.dropout_probability, 0.0, 1.0);
  c.incidence_falloff_exponent = read_in(m, at, "incidence_falloff_exponent", c.incidence_falloff_exponent, 0.0, 10.0);
  c.vertical_offset_sigma_deg = read_in(m, at, "vertical_offset_sigma_deg", c.vertical_offset_sigma_deg, 0.0, 1.0);
  c.temperature_c = read_in(m, at, "temperature_c", c.temperature_c, -40.0, 100.0);
  if (has_key(m, "unit_seed")) s.lidar_unit_seed = read_seed(m, at, "unit_seed", 0);
  c.range_offset_error = read_bool(m, at, "range_offset_error", c.range_offset_error);
  c.range_offset_sigma_m = read_in(m, at, "range_offset_sigma_m", c.range_offset_sigma_m, 0.0, 1.0);
  c.intensity_range_bias = read_bool(m, at, "intensity_range_bias", c.intensity_range_bias);
  c.intensity_range_walk_m = read_in(m, at, "intensity_range_walk_m", c.intensity_range_walk_m, 0.0, 1.0);
  c.dark_surface_dropout = read_bool(m, at, "dark_surface_dropout", c.dark_surface_dropout);
  c.range_at_reference_reflectivity_m =
      read_in(m, at, "range_at_reference_reflectivity_m", c.range_at_reference_reflectivity_m, 1.0, 1000.0);
  c.reference_reflectivity = read_in(m, at, "reference_reflectivity", c.reference_reflectivity, 0.01, 1.0);
  c.mixed_pixels = read_bool(m, at, "mixed_pixels", c.mixed_pixels);
  c.beam_divergence_horizontal_mrad =
      read_in(m, at, "beam_divergence_horizontal_mrad", c.beam_divergence_horizontal_mrad, 0.0, 50.0);
  c.beam_divergence_vertical_mrad =
      read_in(m, at, "beam_divergence_vertical_mrad", c.beam_divergence_vertical_mrad, 0.0, 50.0);
  c.mixed_pixel_max_gap_m = read_in(m, at, "mixed_pixel_max_gap_m", c.mixed_pixel_max_gap_m, 0.0, 100.0);
  if (has_key(m, "cage_bars")) read_cage_bars(section(m, "cage_bars"), at.key("cage_bars"), c.cage_bars);
  link.msop_port = static_cast<std::uint16_t>(read_int_in(m, at, "msop_port", link.msop_port, 1, 65535));
  link.difop_port = static_cast<std::uint16_t>(read_int_in(m, at, "difop_port", link.difop_port, 1, 65535));
  link.network_latency_s = read_in(m, at, "network_latency_s", link.network_latency_s, 0.0, 0.1);
  link.network_jitter_s = read_in(m, at, "network_jitter_s", link.network_jitter_s, 0.0, 0.1);
  link.difop_period_s = read_in(m, at, "difop_period_s", link.difop_period_s, 0.1, 10.0);
  s.difop_phase_s = read_optional_in(m, at, "difop_phase_s", 0.0, link.difop_period_s);
}

Eigen::Vector2d read_xy(const YAML::Node& m, const YamlPath& at, std::string_view key) {
  const YAML::Node n = m[std::string(key)];
  const YamlPath here = at.key(key);
  if (!n || !n.IsSequence() || n.size() != 2) here.fail("must be 2 numbers [x, y] (m)");
  Eigen::Vector2d v;
  for (std::size_t i = 0; i < 2; ++i) {
    try {
      v[static_cast<Eigen::Index>(i)] = n[i].as<double>();
    } catch (const YAML::Exception&) {
      here.index(i).fail("must be a number");
    }
    if (!std::isfinite(v[static_cast<Eigen::Index>(i)])) here.index(i).fail("must be finite");
  }
  return v;
}

void read_walkers(const YAML::Node& m, const YamlPath& at, PeopleConfig& c) {
  check_keys(m, at, {"count", "speed_m_s", "path_length_m", "paths"});
  c.walkers = true;
  c.walker_count = read_int_in(m, at, "count", c.walker_count, 0, 50);
  std::tie(c.walker_min_speed_m_s, c.walker_max_speed_m_s) =
      read_positive_range(m, at, "speed_m_s", {c.walker_min_speed_m_s, c.walker_max_speed_m_s});
  std::tie(c.walker_min_path_m, c.walker_max_path_m) =
      read_positive_range(m, at, "path_length_m", {c.walker_min_path_m, c.walker_max_path_m});
  if (!has_key(m, "paths")) return;
  if (has_key(m, "count")) at.key("count").fail("give either count (paths drawn from the seed) or paths, not both");
  const YAML::Node paths = m["paths"];
  if (!paths.IsSequence() || paths.size() == 0) at.key("paths").fail("must be a non-empty list of {from_m, to_m, speed_m_s, start_m}");
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const YamlPath here = at.key("paths").index(i);
    require_map(paths[i], here);
    check_keys(paths[i], here, {"from_m", "to_m", "speed_m_s", "start_m"});
    WalkerPath w;
    w.from_m = read_xy(paths[i], here, "from_m");
    w.to_m = read_xy(paths[i], here, "to_m");
    w.speed_m_s = read_in(paths[i], here, "speed_m_s", w.speed_m_s, 0.0, 10.0);
    w.start_m = read_in(paths[i], here, "start_m", w.start_m, 0.0, 1e4);
    c.walker_paths.push_back(w);
  }
}

void read_rope_puller(const YAML::Node& m, const YamlPath& at, PeopleConfig& c) {
  check_keys(m, at, {"ahead_m", "surge_m", "surge_period_s", "heading_lag_s"});
  c.rope_puller = true;
  c.puller_ahead_m = read_in(m, at, "ahead_m", c.puller_ahead_m, 0.5, 20.0);
  c.puller_surge_m = read_in(m, at, "surge_m", c.puller_surge_m, 0.0, c.puller_ahead_m - 0.5);
  c.puller_surge_period_s = read_in(m, at, "surge_period_s", c.puller_surge_period_s, 0.5, 600.0);
  c.puller_heading_lag_s = read_in(m, at, "heading_lag_s", c.puller_heading_lag_s, 0.01, 10.0);
}

void read_people(const YAML::Node& m, const YamlPath& at, PeopleConfig& c) {
  check_keys(m, at, {"seed", "radius_m", "height_m", "reflectivity", "floor_z_m", "walkers", "rope_puller"});
  if (has_key(m, "seed")) c.seed = read_seed(m, at, "seed", 0);
  c.radius_m = read_in(m, at, "radius_m", c.radius_m, 0.05, 2.0);
  c.height_m = read_in(m, at, "height_m", c.height_m, 0.1, 3.0);
  c.reflectivity = read_in(m, at, "reflectivity", c.reflectivity, 0.0, 1.0);
  c.floor_z_m = read_in(m, at, "floor_z_m", c.floor_z_m, -1e4, 1e4);
  if (has_key(m, "walkers")) read_walkers(section(m, "walkers"), at.key("walkers"), c);
  if (has_key(m, "rope_puller")) read_rope_puller(section(m, "rope_puller"), at.key("rope_puller"), c);
}

// The people section as read (null when nobody is on).
YAML::Node people_to_yaml(const PeopleConfig& c) {
  YAML::Node n;
  if (c.seed) n["seed"] = *c.seed;
  n["radius_m"] = c.radius_m;
  n["height_m"] = c.height_m;
  n["reflectivity"] = c.reflectivity;
  n["floor_z_m"] = c.floor_z_m;
  if (c.walkers) {
    YAML::Node w;
    if (c.walker_paths.empty()) {
      w["count"] = c.walker_count;
      w["speed_m_s"] = std::vector<double>{c.walker_min_speed_m_s, c.walker_max_speed_m_s};
      w["speed_m_s"].SetStyle(YAML::EmitterStyle::Flow);
      w["path_length_m"] = std::vector<double>{c.walker_min_path_m, c.walker_max_path_m};
      w["path_length_m"].SetStyle(YAML::EmitterStyle::Flow);
    }
    for (const WalkerPath& p : c.walker_paths) {
      YAML::Node path;
      path["from_m"] = std::vector<double>{p.from_m.x(), p.from_m.y()};
      path["to_m"] = std::vector<double>{p.to_m.x(), p.to_m.y()};
      path["from_m"].SetStyle(YAML::EmitterStyle::Flow);
      path["to_m"].SetStyle(YAML::EmitterStyle::Flow);
      path["speed_m_s"] = p.speed_m_s;
      path["start_m"] = p.start_m;
      w["paths"].push_back(path);
    }
    n["walkers"] = w;
  }
  if (c.rope_puller) {
    YAML::Node r;
    r["ahead_m"] = c.puller_ahead_m;
    r["surge_m"] = c.puller_surge_m;
    r["surge_period_s"] = c.puller_surge_period_s;
    r["heading_lag_s"] = c.puller_heading_lag_s;
    n["rope_puller"] = r;
  }
  return n;
}

void read_imu(const YAML::Node& m, const YamlPath& at, Scenario& s) {
  check_keys(m, at,
             {"rate_hz", "noise", "gyro_noise_density_deg_s_sqrt_hz", "accel_noise_density_ug_sqrt_hz",
              "gyro_initial_bias_sigma_deg_s", "accel_initial_bias_sigma_m_s2", "gyro_bias_stability_deg_h",
              "accel_bias_stability_ug", "gyro_range_deg_s", "accel_range_m_s2", "clock_drift_ppm",
              "sample_time_fine_start_s", "baud", "processing_latency_s", "read_latency_s", "read_jitter_s",
              "number_format", "leading_garbage_bytes", "leading_config_ack", "scale_factor_error",
              "gyro_scale_factor_sigma_pct", "accel_scale_factor_sigma_pct", "misalignment", "misalignment_sigma_deg",
              "g_sensitivity", "gyro_g_sensitivity_deg_s_per_g", "temperature_drift", "gyro_temperature_drift_deg_s",
              "accel_temperature_drift_m_s2", "warm_up_time_constant_s", "timestamp_jitter", "timestamp_jitter_s",
              "vibration", "vibration_accel_m_s2_per_m_s", "vibration_accel_per_m_s2", "vibration_gyro_deg_s_per_m_s",
              "vibration_gyro_deg_s_per_m_s2"});
  ImuConfig& c = s.imu;
  ImuLinkConfig& link = s.imu_link;
  c.rate_hz = read_int_in(m, at, "rate_hz", c.rate_hz, 1, 400);
  if (400 % c.rate_hz != 0)
    at.key("rate_hz").fail("must divide 400 (the MTi's base rate): 1, 2, 4, 5, 8, 10, 16, 20, 25, 40, 50, 80, 100, 200 or 400");
  s.imu_noise = read_bool(m, at, "noise", s.imu_noise);
  c.gyro_noise_density_deg_s_sqrt_hz = read_in(m, at, "gyro_noise_density_deg_s_sqrt_hz", c.gyro_noise_density_deg_s_sqrt_hz, 0.0, 10.0);
  c.accel_noise_density_ug_sqrt_hz = read_in(m, at, "accel_noise_density_ug_sqrt_hz", c.accel_noise_density_ug_sqrt_hz, 0.0, 1e5);
  c.gyro_initial_bias_sigma_deg_s = read_in(m, at, "gyro_initial_bias_sigma_deg_s", c.gyro_initial_bias_sigma_deg_s, 0.0, 10.0);
  c.accel_initial_bias_sigma_m_s2 = read_in(m, at, "accel_initial_bias_sigma_m_s2", c.accel_initial_bias_sigma_m_s2, 0.0, 10.0);
  c.gyro_bias_stability_deg_h = read_in(m, at, "gyro_bias_stability_deg_h", c.gyro_bias_stability_deg_h, 0.0, 1e4);
  c.accel_bias_stability_ug = read_in(m, at, "accel_bias_stability_ug", c.accel_bias_stability_ug, 0.0, 1e5);
  c.gyro_range_deg_s = read_in(m, at, "gyro_range_deg_s", c.gyro_range_deg_s, 1.0, 1e4);
  c.accel_range_m_s2 = read_in(m, at, "accel_range_m_s2", c.accel_range_m_s2, 1.0, 1e4);
  c.scale_factor_error = read_bool(m, at, "scale_factor_error", c.scale_factor_error);
  c.gyro_scale_factor_sigma_pct = read_in(m, at, "gyro_scale_factor_sigma_pct", c.gyro_scale_factor_sigma_pct, 0.0, 10.0);
  c.accel_scale_factor_sigma_pct = read_in(m, at, "accel_scale_factor_sigma_pct", c.accel_scale_factor_sigma_pct, 0.0, 10.0);
  c.misalignment = read_bool(m, at, "misalignment", c.misalignment);
  c.misalignment_sigma_deg = read_in(m, at, "misalignment_sigma_deg", c.misalignment_sigma_deg, 0.0, 5.0);
  c.g_sensitivity = read_bool(m, at, "g_sensitivity", c.g_sensitivity);
  c.gyro_g_sensitivity_deg_s_per_g = read_in(m, at, "gyro_g_sensitivity_deg_s_per_g", c.gyro_g_sensitivity_deg_s_per_g, 0.0, 1.0);
  c.temperature_drift = read_bool(m, at, "temperature_drift", c.temperature_drift);
  c.gyro_temperature_drift_deg_s = read_in(m, at, "gyro_temperature_drift_deg_s", c.gyro_temperature_drift_deg_s, 0.0, 10.0);
  c.accel_temperature_drift_m_s2 = read_in(m, at, "accel_temperature_drift_m_s2", c.accel_temperature_drift_m_s2, 0.0, 10.0);
  c.warm_up_time_constant_s = read_in(m, at, "warm_up_time_constant_s", c.warm_up_time_constant_s, 1.0, 1e5);
  c.timestamp_jitter = read_bool(m, at, "timestamp_jitter", c.timestamp_jitter);
  c.timestamp_jitter_s = read_in(m, at, "timestamp_jitter_s", c.timestamp_jitter_s, 0.0, 0.01);
  c.vibration = read_bool(m, at, "vibration", c.vibration);
  c.vibration_accel_m_s2_per_m_s = read_in(m, at, "vibration_accel_m_s2_per_m_s", c.vibration_accel_m_s2_per_m_s, 0.0, 100.0);
  c.vibration_accel_per_m_s2 = read_in(m, at, "vibration_accel_per_m_s2", c.vibration_accel_per_m_s2, 0.0, 10.0);
  c.vibration_gyro_deg_s_per_m_s = read_in(m, at, "vibration_gyro_deg_s_per_m_s", c.vibration_gyro_deg_s_per_m_s, 0.0, 100.0);
  c.vibration_gyro_deg_s_per_m_s2 = read_in(m, at, "vibration_gyro_deg_s_per_m_s2", c.vibration_gyro_deg_s_per_m_s2, 0.0, 10.0);
  s.imu_clock_drift_ppm = read_optional_in(m, at, "clock_drift_ppm", -1000.0, 1000.0);
  s.imu_sample_time_start_s = read_optional_in(m, at, "sample_time_fine_start_s", 0.0, 86399.0);
  link.baud = read_int_in(m, at, "baud", link.baud, 9600, 4'000'000);
  link.processing_latency_s = read_in(m, at, "processing_latency_s", link.processing_latency_s, 0.0, 0.1);
  link.read_latency_s = read_in(m, at, "read_latency_s", link.read_latency_s, 1e-6, 0.1);
  link.read_jitter_s = read_in(m, at, "read_jitter_s", link.read_jitter_s, 0.0, 0.1);
  link.number_format =
      parse_number_format(at.key("number_format"), read_string(m, at, "number_format", number_format_key(link.number_format)));
  link.leading_garbage_bytes = read_int_in(m, at, "leading_garbage_bytes", link.leading_garbage_bytes, 0, 40);
  link.leading_config_ack = read_bool(m, at, "leading_config_ack", link.leading_config_ack);
  // The UART must keep up, or frames would queue without bound.
  const std::size_t frame_bytes = mtdata2_frame_bytes(link.number_format);
  const double bits_per_s = static_cast<double>(frame_bytes) * c.rate_hz * 10.0;
  if (bits_per_s > 0.95 * link.baud) {
    at.key("baud").fail(std::to_string(link.baud) + " is too slow for " + std::to_string(c.rate_hz) + " Hz frames of " +
                        std::to_string(frame_bytes) + " bytes (needs at least " +
                        std::to_string(static_cast<long>(bits_per_s / 0.95) + 1) + ")");
  }
}

}  // namespace

std::filesystem::path sim_data_dir(const std::string& kind) {
  return std::filesystem::path(TUMBLE_SIM_SCENES_DIR).parent_path() / kind;
}

std::filesystem::path default_scenario_path() { return sim_data_dir("scenarios") / "default.yaml"; }

const char* number_format_key(mti::NumberFormat f) {
  switch (f) {
    case mti::NumberFormat::Float32: return "float32";
    case mti::NumberFormat::Fp1220: return "fp1220";
    case mti::NumberFormat::Fp1632: return "fp1632";
    case mti::NumberFormat::Float64: return "float64";
  }
  return "float32";
}

std::string format_utc(std::int64_t t_ns) {
  const std::time_t seconds = static_cast<std::time_t>(t_ns / 1'000'000'000);
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  char text[64];
  std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%02d.%06lldZ", tm.tm_year + 1900, tm.tm_mon + 1,
                tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec,
                static_cast<long long>((t_ns % 1'000'000'000) / 1000));
  return text;
}

Scenario parse_scenario(const YAML::Node& root, const std::string& source_name, const std::filesystem::path& base_dir) {
  Scenario s;
  s.source_name = source_name;
  const YamlPath at{source_name, ""};
  check_keys(root, at,
             {"scene", "motion", "seed", "motion_seed", "duration_s", "epoch_utc", "ground_truth_rate_hz", "extrinsics",
              "lidar", "imu", "people"});

  s.scene_ref = read_string(root, at, "scene");
  s.scene_path = resolve_ref(s.scene_ref, "scenes", base_dir);
  if (!std::filesystem::exists(s.scene_path)) at.key("scene").fail("no such scene: " + s.scene_path.string());

  const YAML::Node motion = root["motion"];
  if (!motion || motion.IsNull()) at.key("motion").fail("missing (a motion name under tools/sim/motions, a path, or a map)");
  if (motion.IsMap()) {
    s.motion_ref = "inline";
    s.motion = YAML::Clone(motion);
  } else if (motion.IsScalar()) {
    s.motion_ref = motion.Scalar();
    const auto path = resolve_ref(s.motion_ref, "motions", base_dir);
    if (!std::filesystem::exists(path)) at.key("motion").fail("no such motion: " + path.string());
    s.motion = load_yaml_file(path.string());
  } else {
    at.key("motion").fail("must be a name, a path or a map");
  }

  s.seed = read_seed(root, at, "seed", s.seed);
  if (has_key(root, "motion_seed")) s.motion_seed = read_seed(root, at, "motion_seed", 0);
  s.duration_s = read_optional_in(root, at, "duration_s", 0.01, 3600.0);
  const std::string epoch = read_string(root, at, "epoch_utc", kDefaultEpoch);
  const auto epoch_ns = parse_utc(epoch);
  if (!epoch_ns) at.key("epoch_utc").fail("must be like 2021-05-26T12:00:00Z (UTC, years 2000..2200), got '" + epoch + "'");
  s.epoch_ns = *epoch_ns;
  s.ground_truth_rate_hz = read_in(root, at, "ground_truth_rate_hz", s.ground_truth_rate_hz, 1000.0, 100'000.0);

  const YAML::Node extrinsics = section(root, "extrinsics");
  check_keys(extrinsics, at.key("extrinsics"), {"T_LI", "imu_time_offset_s"});
  s.T_LI = read_pose(section(extrinsics, "T_LI"), at.key("extrinsics").key("T_LI"));
  s.imu_time_offset_s = read_in(extrinsics, at.key("extrinsics"), "imu_time_offset_s", 0.0, -1.0, 1.0);
  read_lidar(section(root, "lidar"), at.key("lidar"), s);
  read_imu(section(root, "imu"), at.key("imu"), s);
  read_people(section(root, "people"), at.key("people"), s.people);
  return s;
}

Scenario load_scenario(const std::filesystem::path& path) {
  return parse_scenario(load_yaml_file(path.string()), path.filename().string(), path.parent_path());
}

YAML::Node scenario_to_yaml(const Scenario& s) {
  YAML::Node n;
  n["scene"] = s.scene_path.string();
  n["motion"] = s.motion;
  n["seed"] = s.seed;
  if (s.motion_seed) n["motion_seed"] = *s.motion_seed;
  if (s.duration_s) n["duration_s"] = *s.duration_s;
  n["epoch_utc"] = format_utc(s.epoch_ns);
  n["ground_truth_rate_hz"] = s.ground_truth_rate_hz;

  const Eigen::Vector3d t = s.T_LI.translation();
  // Inverse of R = Rz(yaw) Ry(pitch) Rx(roll).
  const Eigen::Matrix3d R = s.T_LI.linear();
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double roll = std::atan2(R(2, 1), R(2, 2)), yaw = std::atan2(R(1, 0), R(0, 0));
  YAML::Node pose;
  pose["translation_m"] = std::vector<double>{t.x(), t.y(), t.z()};
  pose["rpy_deg"] = std::vector<double>{roll / kDegToRad, pitch / kDegToRad, yaw / kDegToRad};
  pose["translation_m"].SetStyle(YAML::EmitterStyle::Flow);
  pose["rpy_deg"].SetStyle(YAML::EmitterStyle::Flow);
  n["extrinsics"]["T_LI"] = pose;
  n["extrinsics"]["imu_time_offset_s"] = s.imu_time_offset_s;

  YAML::Node l;
  l["rpm"] = s.lidar.rpm;
  l["range_noise_m"] = s.lidar.range_noise_m;
  l["min_range_m"] = s.lidar.min_range_m;
  l["max_range_m"] = s.lidar.max_range_m;
  l["dropout_probability"] = s.lidar.dropout_probability;
  l["incidence_falloff_exponent"] = s.lidar.incidence_falloff_exponent;
  l["vertical_offset_sigma_deg"] = s.lidar.vertical_offset_sigma_deg;
  l["temperature_c"] = s.lidar.temperature_c;
  l["msop_port"] = s.lidar_link.msop_port;
  l["difop_port"] = s.lidar_link.difop_port;
  l["network_latency_s"] = s.lidar_link.network_latency_s;
  l["network_jitter_s"] = s.lidar_link.network_jitter_s;
  l["difop_period_s"] = s.lidar_link.difop_period_s;
  if (s.difop_phase_s) l["difop_phase_s"] = *s.difop_phase_s;
  if (s.lidar_unit_seed) l["unit_seed"] = *s.lidar_unit_seed;
  // Error sources only when on, so the files of runs without them stay as they were.
  if (s.lidar.range_offset_error) {
    l["range_offset_error"] = true;
    l["range_offset_sigma_m"] = s.lidar.range_offset_sigma_m;
  }
  if (s.lidar.intensity_range_bias) {
    l["intensity_range_bias"] = true;
    l["intensity_range_walk_m"] = s.lidar.intensity_range_walk_m;
  }
  if (s.lidar.dark_surface_dropout) {
    l["dark_surface_dropout"] = true;
    l["range_at_reference_reflectivity_m"] = s.lidar.range_at_reference_reflectivity_m;
    l["reference_reflectivity"] = s.lidar.reference_reflectivity;
  }
  if (s.lidar.mixed_pixels) {
    l["mixed_pixels"] = true;
    l["beam_divergence_horizontal_mrad"] = s.lidar.beam_divergence_horizontal_mrad;
    l["beam_divergence_vertical_mrad"] = s.lidar.beam_divergence_vertical_mrad;
    l["mixed_pixel_max_gap_m"] = s.lidar.mixed_pixel_max_gap_m;
  }
  if (s.lidar.cage_bars.enabled) {
    const CageBars& b = s.lidar.cage_bars;
    YAML::Node bars;
    bars["count"] = b.count;
    bars["cage_radius_m"] = b.cage_radius_m;
    bars["bar_radius_m"] = b.bar_radius_m;
    bars["length_m"] = b.length_m;
    bars["axis"] = std::vector<double>{b.axis_l.x(), b.axis_l.y(), b.axis_l.z()};
    bars["centre_m"] = std::vector<double>{b.centre_l.x(), b.centre_l.y(), b.centre_l.z()};
    bars["axis"].SetStyle(YAML::EmitterStyle::Flow);
    bars["centre_m"].SetStyle(YAML::EmitterStyle::Flow);
    bars["reflectivity"] = b.reflectivity;
    l["cage_bars"] = bars;
  }
  n["lidar"] = l;

  YAML::Node i;
  i["rate_hz"] = s.imu.rate_hz;
  i["noise"] = s.imu_noise;
  i["gyro_noise_density_deg_s_sqrt_hz"] = s.imu.gyro_noise_density_deg_s_sqrt_hz;
  i["accel_noise_density_ug_sqrt_hz"] = s.imu.accel_noise_density_ug_sqrt_hz;
  i["gyro_initial_bias_sigma_deg_s"] = s.imu.gyro_initial_bias_sigma_deg_s;
  i["accel_initial_bias_sigma_m_s2"] = s.imu.accel_initial_bias_sigma_m_s2;
  i["gyro_bias_stability_deg_h"] = s.imu.gyro_bias_stability_deg_h;
  i["accel_bias_stability_ug"] = s.imu.accel_bias_stability_ug;
  i["gyro_range_deg_s"] = s.imu.gyro_range_deg_s;
  i["accel_range_m_s2"] = s.imu.accel_range_m_s2;
  if (s.imu_clock_drift_ppm) i["clock_drift_ppm"] = *s.imu_clock_drift_ppm;
  if (s.imu_sample_time_start_s) i["sample_time_fine_start_s"] = *s.imu_sample_time_start_s;
  i["baud"] = s.imu_link.baud;
  i["processing_latency_s"] = s.imu_link.processing_latency_s;
  i["read_latency_s"] = s.imu_link.read_latency_s;
  i["read_jitter_s"] = s.imu_link.read_jitter_s;
  i["number_format"] = number_format_key(s.imu_link.number_format);
  i["leading_garbage_bytes"] = s.imu_link.leading_garbage_bytes;
  i["leading_config_ack"] = s.imu_link.leading_config_ack;
  // Error sources only when on, so the files of runs without them stay as they were.
  if (s.imu.scale_factor_error) {
    i["scale_factor_error"] = true;
    i["gyro_scale_factor_sigma_pct"] = s.imu.gyro_scale_factor_sigma_pct;
    i["accel_scale_factor_sigma_pct"] = s.imu.accel_scale_factor_sigma_pct;
  }
  if (s.imu.misalignment) {
    i["misalignment"] = true;
    i["misalignment_sigma_deg"] = s.imu.misalignment_sigma_deg;
  }
  if (s.imu.g_sensitivity) {
    i["g_sensitivity"] = true;
    i["gyro_g_sensitivity_deg_s_per_g"] = s.imu.gyro_g_sensitivity_deg_s_per_g;
  }
  if (s.imu.temperature_drift) {
    i["temperature_drift"] = true;
    i["gyro_temperature_drift_deg_s"] = s.imu.gyro_temperature_drift_deg_s;
    i["accel_temperature_drift_m_s2"] = s.imu.accel_temperature_drift_m_s2;
    i["warm_up_time_constant_s"] = s.imu.warm_up_time_constant_s;
  }
  if (s.imu.timestamp_jitter) {
    i["timestamp_jitter"] = true;
    i["timestamp_jitter_s"] = s.imu.timestamp_jitter_s;
  }
  if (s.imu.vibration) {
    i["vibration"] = true;
    i["vibration_accel_m_s2_per_m_s"] = s.imu.vibration_accel_m_s2_per_m_s;
    i["vibration_accel_per_m_s2"] = s.imu.vibration_accel_per_m_s2;
    i["vibration_gyro_deg_s_per_m_s"] = s.imu.vibration_gyro_deg_s_per_m_s;
    i["vibration_gyro_deg_s_per_m_s2"] = s.imu.vibration_gyro_deg_s_per_m_s2;
  }
  n["imu"] = i;
  // Only when someone is there, so the files of runs without people stay as they were.
  if (s.people.any()) n["people"] = people_to_yaml(s.people);
  return n;
}

}  // namespace tumble::sim
