#include "daemon/config.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <utility>

namespace tumble::daemon {
namespace {

// ---- constraints: what a key allows ----------------------------------------

struct Range {  // inclusive
  double lo, hi;
};
struct IntRange {  // inclusive
  int lo, hi;
};
struct IntSet {
  std::span<const int> values;
};
template <class E>
struct Choice {
  std::span<const std::pair<std::string_view, E>> names;
};
struct AnyText {};
struct NonEmptyText {};
struct Ipv4Address {
  bool allow_empty;
};
struct LcmUrl {};
struct Angles {  // a list of 0 or `count` values in range
  std::size_t count;
  Range range;
};

constexpr std::pair<std::string_view, WeightModel> kModels[] = {{"NM", WeightModel::NM},
                                                                {"TW", WeightModel::TW},
                                                                {"VTW", WeightModel::VTW},
                                                                {"GVTW", WeightModel::GVTW},
                                                                {"SAW", WeightModel::SAW}};
constexpr std::pair<std::string_view, LidarClock> kClocks[] = {{"synced", LidarClock::Synced},
                                                               {"free", LidarClock::Free}};
constexpr std::pair<std::string_view, ReadingNormalSource> kReadingNormalSources[] = {
    {"knn", ReadingNormalSource::kNearest}, {"scan_lines", ReadingNormalSource::kScanLines}};
constexpr std::pair<std::string_view, AttitudeSource> kAttitudeSources[] = {{"madgwick", AttitudeSource::Madgwick},
                                                                            {"device", AttitudeSource::Device}};
constexpr std::pair<std::string_view, LogLevel> kLogLevels[] = {
    {"trace", LogLevel::Trace}, {"debug", LogLevel::Debug},       {"info", LogLevel::Info}, {"warn", LogLevel::Warn},
    {"error", LogLevel::Error}, {"critical", LogLevel::Critical}, {"off", LogLevel::Off}};
constexpr int kBauds[] = {9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600, 2000000};

// ---- the schema: every key, its member and its constraint, in file order ----

// Config is DaemonConfig for the reader and const DaemonConfig for the writer and checker.
template <class Visitor, class Config>
void visit_config(Visitor& v, Config& c) {
  v.section("lidar", [&] {
    auto& l = c.lidar;
    v.field("bind_address", l.bind_address, Ipv4Address{false});
    v.field("msop_port", l.msop_port, IntRange{1, 65535});
    v.field("difop_port", l.difop_port, IntRange{1, 65535});
    v.field("source_ip", l.source_ip, Ipv4Address{true});
    v.field("split_azimuth_deg", l.split_azimuth_deg, Range{0.0, 360.0});
    v.field("min_scan_coverage", l.min_scan_coverage, Range{0.0, 1.0});
    v.field("min_range_m", l.min_range_m, Range{0.0, 300.0});
    v.field("max_range_m", l.max_range_m, Range{0.1, 300.0});
    v.field("clock", l.clock, Choice<LidarClock>{kClocks});
    v.field("vertical_angles_deg", l.vertical_angles_deg, Angles{16, Range{-25.0, 25.0}});
    v.field("follow_difop_changes", l.follow_difop_changes, AnyText{});
    v.field("receive_buffer_bytes", l.receive_buffer_bytes, IntRange{65536, 1 << 30});
  });
  v.section("imu", [&] {
    auto& i = c.imu;
    v.field("device", i.device, NonEmptyText{});
    v.field("baud", i.baud, IntSet{kBauds});
    v.field("configure", i.configure, AnyText{});
    v.field("rate_hz", i.rate_hz, IntRange{1, 1000});
    v.field("imu_time_offset_s", i.imu_time_offset_s, Range{-1.0, 1.0});
    v.section("extrinsic_T_LI", [&] {
      auto& e = i.extrinsic_T_LI;
      v.field("translation_m", e.translation_m, Range{-10.0, 10.0});
      v.one_of("rotation_rpy_deg", e.rotation_rpy_deg, Range{-360.0, 360.0}, "rotation_quaternion_wxyz",
               e.rotation_quaternion_wxyz, Range{-1.0, 1.0});
    });
    v.field("gyro_noise_density_deg_s_sqrt_hz", i.gyro_noise_density_deg_s_sqrt_hz, Range{0.0, 10.0});
    v.field("accel_noise_density_ug_sqrt_hz", i.accel_noise_density_ug_sqrt_hz, Range{0.0, 100000.0});
    v.field("gyro_range_deg_s", i.gyro_range_deg_s, Range{1.0, 10000.0});
    v.field("accel_range_m_s2", i.accel_range_m_s2, Range{1.0, 10000.0});
  });
  v.section("fuser", [&] {
    auto& f = c.fuser;
    v.field("madgwick_beta", f.madgwick_beta, Range{0.0, 1.0});
    v.field("accel_gate_m_s2", f.accel_gate_m_s2, Range{0.01, 100.0});
    v.field("accel_correction_after_s", f.accel_correction_after_s, Range{0.0, 600.0});
    v.field("levelling_max_expected_error_m", f.levelling_max_expected_error_m, Range{0.0, 10.0});
    v.field("levelling_max_rotation_error_deg", f.levelling_max_rotation_error_deg, Range{0.0, 180.0});
    v.field("init_static_s", f.init_static_s, Range{0.0, 60.0});
    v.field("rest_static_s", f.rest_static_s, Range{0.0, 60.0});
    v.field("max_speed_m_s", f.max_speed_m_s, Range{0.1, 1000.0});
    v.field("max_speed_at_rest_m_s", f.max_speed_at_rest_m_s, Range{0.01, 1000.0});
    v.field("attitude_source", f.attitude_source, Choice<AttitudeSource>{kAttitudeSources});
  });
  v.section("registration", [&] {
    auto& r = c.registration;
    v.field("model", r.model, Choice<WeightModel>{kModels});
    v.field("deskew", r.deskew, AnyText{});
    v.field("voxel_size_m", r.voxel_size_m, Range{0.005, 1.0});
    v.field("icp_voxel_size_m", r.icp_voxel_size_m, Range{0.0, 2.0});
    v.field("normal_k_map", r.normal_k_map, IntRange{3, 200});
    v.field("normal_k_reading", r.normal_k_reading, IntRange{3, 200});
    v.field("reading_normals", r.reading_normals, Choice<ReadingNormalSource>{kReadingNormalSources});
    v.field("scan_line_points_each_side", r.scan_line_points_each_side, IntRange{1, 50});
    v.field("scan_line_rings_each_side", r.scan_line_rings_each_side, IntRange{1, 8});
    v.field("max_match_distance_m", r.max_match_distance_m, Range{0.01, 10.0});
    v.field("match_k", r.match_k, IntRange{1, 32});
    v.field("frmsd_min_ratio", r.frmsd_min_ratio, Range{0.05, 1.0});
    v.field("frmsd_max_ratio", r.frmsd_max_ratio, Range{0.05, 1.0});
    v.field("frmsd_lambda", r.frmsd_lambda, Range{0.0, 10.0});
    v.field("max_iterations", r.max_iterations, IntRange{1, 1000});
    v.field("convergence_translation_m", r.convergence_translation_m, Range{0.0, 1.0});
    v.field("convergence_rotation_rad", r.convergence_rotation_rad, Range{0.0, 1.0});
    v.field("convergence_window_iterations", r.convergence_window_iterations, IntRange{1, 10});
    v.field("unobserved_min_eigenvalue", r.unobserved_min_eigenvalue, Range{0.0, 1.0});
    v.field("unobserved_window_scans", r.unobserved_window_scans, IntRange{1, 1000});
    v.field("unobserved_fraction", r.unobserved_fraction, Range{0.01, 1.0});
    v.field("unobserved_sigma_m", r.unobserved_sigma_m, Range{0.001, 1000.0});
    v.field("hold_weak_translation", r.hold_weak_translation, AnyText{});
    v.field("prediction_sigma_m", r.prediction_sigma_m, Range{0.0, 10.0});
    v.field("jump_sigmas", r.jump_sigmas, Range{0.0, 1000.0});
    v.field("sigma_n_floor_m", r.sigma_n_floor_m, Range{0.0, 1.0});
    v.field("sigma_n_beam_rad", r.sigma_n_beam_rad, Range{0.0, 0.1});
    v.field("tw_c1_m_s", r.tw_c1_m_s, Range{0.0, 100.0});
    v.field("vtw_c2", r.vtw_c2, Range{0.0, 100.0});
    v.field("gvtw_c3", r.gvtw_c3, Range{0.0, 100.0});
    v.field("saw_c_r", r.saw_c_r, Range{0.001, 1.0 / 3.0});
    v.field("lognormal_beta", r.lognormal_beta, Range{0.01, 10.0});
    v.field("lognormal_kappa_m_s", r.lognormal_kappa_m_s, Range{0.01, 100.0});
    v.field("lognormal_lambda", r.lognormal_lambda, Range{0.0, 100.0});
    v.field("cubic_phi_rad_s", r.cubic_phi_rad_s, Range{0.01, 1000.0});
    v.field("no_deskew_sigma_v_ratio", r.no_deskew_sigma_v_ratio, Range{0.0, 10.0});
    v.field("no_deskew_sigma_omega_ratio", r.no_deskew_sigma_omega_ratio, Range{0.0, 10.0});
    v.field("corner_point_uncertainty_m", r.corner_point_uncertainty_m, Range{0.0, 10.0});
  });
  v.section("map", [&] {
    auto& m = c.map;
    v.field("radius_m", m.radius_m, Range{1.0, 1000.0});
    v.field("min_point_distance_m", m.min_point_distance_m, Range{0.0, 1.0});
    v.field("max_sigma_m", m.max_sigma_m, Range{0.0, 100.0});
    v.field("voxel_size_m", m.voxel_size_m, Range{0.05, 10.0});
    v.field("points_per_voxel", m.points_per_voxel, IntRange{1, 10000});
    v.field("remove_seen_through", m.remove_seen_through, AnyText{});
    v.field("seen_through_beam_radius_m", m.seen_through_beam_radius_m, Range{0.005, 1.0});
    v.field("seen_through_margin_m", m.seen_through_margin_m, Range{0.0, 10.0});
    v.field("seen_through_max_range_m", m.seen_through_max_range_m, Range{1.0, 200.0});
    v.field("seen_through_max_expected_error_m", m.seen_through_max_expected_error_m, Range{0.001, 10.0});
    v.field("seen_through_beam_stride", m.seen_through_beam_stride, IntRange{1, 64});
  });
  v.section("lcm", [&] {
    v.field("url", c.lcm.url, LcmUrl{});
    v.field("channel_prefix", c.lcm.channel_prefix, AnyText{});
    v.field("publish_scan", c.lcm.publish_scan, AnyText{});
    v.field("publish_map_period_s", c.lcm.publish_map_period_s, Range{0.0, 3600.0});
  });
  v.section("daemon", [&] {
    auto& d = c.daemon;
    v.field("imu_ring_capacity", d.imu_ring_capacity, IntRange{2, 65534});
    v.field("lidar_ring_capacity", d.lidar_ring_capacity, IntRange{2, 65534});
    v.field("correction_ring_capacity", d.correction_ring_capacity, IntRange{2, 65534});
    v.field("odometry_ring_capacity", d.odometry_ring_capacity, IntRange{2, 65534});
    v.field("registration_ring_capacity", d.registration_ring_capacity, IntRange{2, 65534});
    v.field("scan_report_ring_capacity", d.scan_report_ring_capacity, IntRange{2, 65534});
    v.field("trajectory_buffer_capacity", d.trajectory_buffer_capacity, IntRange{64, 1 << 20});
    v.field("trajectory_wait_s", d.trajectory_wait_s, Range{0.0, 10.0});
    v.field("realtime_priority", d.realtime_priority, IntRange{0, 99});
    v.field("registration_nice", d.registration_nice, IntRange{0, 19});
    v.field("registration_threads", d.registration_threads, IntRange{1, 64});
    v.field("log_level", d.log_level, Choice<LogLevel>{kLogLevels});
    v.field("status_period_s", d.status_period_s, Range{0.1, 60.0});
    v.field("checkpoint_period_s", d.checkpoint_period_s, Range{0.1, 60.0});
    v.section("health", [&] {
      auto& h = d.health;
      v.field("sensor_timeout_s", h.sensor_timeout_s, Range{0.01, 60.0});
      v.field("degraded_to_lost_s", h.degraded_to_lost_s, Range{0.0, 600.0});
      v.field("lidar_silent_to_lost_s", h.lidar_silent_to_lost_s, Range{0.1, 600.0});
      v.field("scan_timeout_s", h.scan_timeout_s, Range{0.05, 600.0});
      v.field("good_scans_to_recover", h.good_scans_to_recover, IntRange{1, 1000});
      v.field("min_matched_ratio", h.min_matched_ratio, Range{0.0, 1.0});
      v.field("min_matched_ratio_spin_clipped", h.min_matched_ratio_spin_clipped, Range{0.0, 1.0});
      v.field("spin_clipped_scans_to_settle", h.spin_clipped_scans_to_settle, IntRange{0, 1000});
      v.field("min_degeneracy", h.min_degeneracy, Range{0.0, 1.0});
      v.field("max_expected_error_m", h.max_expected_error_m, Range{0.001, 10.0});
      v.field("second_lidar_rate_hz", h.second_lidar_rate_hz, Range{1.0, 100000.0});
    });
  });
  v.section("record", [&] {
    v.field("dir", c.record.dir, AnyText{});
    v.field("max_segment_mib", c.record.max_segment_mib, IntRange{1, 1 << 20});
    v.field("max_segment_s", c.record.max_segment_s, Range{1.0, 86400.0});
    v.field("min_free_mib", c.record.min_free_mib, IntRange{0, 1 << 20});
  });
}

// ---- checks shared by the loader and validate() -----------------------------

[[noreturn]] void fail(const std::string& message) { throw ConfigError(message); }

std::string number(double value) { return fmt::format("{}", value); }

void check(const std::string& path, double value, Range r) {
  if (!(value >= r.lo && value <= r.hi))  // written so that NaN fails too
    fail(fmt::format("{}: {} is out of range ({}..{})", path, number(value), number(r.lo), number(r.hi)));
}
void check(const std::string& path, int value, IntRange r) {
  if (value < r.lo || value > r.hi) fail(fmt::format("{}: {} is out of range ({}..{})", path, value, r.lo, r.hi));
}
void check(const std::string& path, int value, IntSet s) {
  if (std::find(s.values.begin(), s.values.end(), value) == s.values.end())
    fail(fmt::format("{}: {} is not one of {}", path, value, fmt::join(s.values, ", ")));
}
template <class E>
void check(const std::string&, E, Choice<E>) {}  // a typed enum is always one of its names
void check(const std::string&, bool, AnyText) {}
void check(const std::string&, const std::string&, AnyText) {}
void check(const std::string& path, const std::string& value, NonEmptyText) {
  if (value.empty()) fail(path + ": must not be empty");
}
void check(const std::string& path, const std::string& value, Ipv4Address a) {
  if (a.allow_empty && value.empty()) return;
  in_addr parsed{};
  if (::inet_pton(AF_INET, value.c_str(), &parsed) != 1)
    fail(fmt::format("{}: \"{}\" is not an IPv4 address (like 192.168.1.200){}", path, value,
                     a.allow_empty ? " or empty" : ""));
}
void check(const std::string& path, const std::string& value, LcmUrl) {
  const auto scheme_end = value.find("://");
  if (scheme_end == std::string::npos || scheme_end == 0)
    fail(fmt::format("{}: \"{}\" is not an LCM URL (provider://network?options, e.g. udpm://239.255.76.67:7667?ttl=0)",
                     path, value));
}
template <std::size_t N>
void check(const std::string& path, const std::array<double, N>& values, Range r) {
  for (std::size_t i = 0; i < N; ++i) check(fmt::format("{}[{}]", path, i), values[i], r);
}
void check(const std::string& path, const std::vector<double>& values, Angles a) {
  if (!values.empty() && values.size() != a.count)
    fail(fmt::format("{}: has {} values; give none (use the lidar's own) or exactly {}", path, values.size(), a.count));
  for (std::size_t i = 0; i < values.size(); ++i) check(fmt::format("{}[{}]", path, i), values[i], a.range);
}

// Rules that tie keys together; messages name both keys.
void check_consistency(const DaemonConfig& c) {
  if (c.lidar.min_range_m >= c.lidar.max_range_m)
    fail(fmt::format("lidar.min_range_m: {} must be below lidar.max_range_m ({})", number(c.lidar.min_range_m),
                     number(c.lidar.max_range_m)));
  if (c.lidar.msop_port == c.lidar.difop_port)
    fail(fmt::format("lidar.difop_port: {} must differ from lidar.msop_port", c.lidar.difop_port));
  if (c.registration.frmsd_min_ratio > c.registration.frmsd_max_ratio)
    fail(fmt::format("registration.frmsd_min_ratio: {} must not exceed registration.frmsd_max_ratio ({})",
                     number(c.registration.frmsd_min_ratio), number(c.registration.frmsd_max_ratio)));
  if (c.imu.configure) {
    if (c.imu.rate_hz > 400)
      fail(fmt::format("imu.rate_hz: {} is above the 400 Hz the MTi can be configured to (imu.configure: true)",
                       c.imu.rate_hz));
    // The 54-byte MTData2 frame we configure, 10 bits a byte, with the line at most half busy
    // (docs/sensors.md: 400 Hz needs 460800 baud).
    const int needed_baud = 2 * 10 * 54 * c.imu.rate_hz;
    if (c.imu.baud < needed_baud)
      fail(fmt::format("imu.rate_hz: {} Hz needs at least {} baud, imu.baud is {}", c.imu.rate_hz, needed_baud,
                       c.imu.baud));
  }
  const ExtrinsicConfig& e = c.imu.extrinsic_T_LI;
  if (e.rotation_rpy_deg.has_value() == e.rotation_quaternion_wxyz.has_value())
    fail("imu.extrinsic_T_LI: give exactly one of rotation_rpy_deg and rotation_quaternion_wxyz");
  if (e.rotation_quaternion_wxyz) {
    const auto& q = *e.rotation_quaternion_wxyz;
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(std::abs(norm - 1.0) <= 0.01))
      fail(fmt::format("imu.extrinsic_T_LI.rotation_quaternion_wxyz: norm {} is not 1 (+-0.01)", number(norm)));
  }
}

// ---- the checker: validate() on a struct built in code ----------------------

class Checker {
 public:
  template <class Body>
  void section(std::string_view name, Body&& body) {
    const std::size_t size = path_.size();
    path_ += path_.empty() ? std::string(name) : "." + std::string(name);
    body();
    path_.resize(size);
  }
  template <class T, class C>
  void field(std::string_view name, const T& value, const C& constraint) {
    check(key(name), value, constraint);
  }
  template <class A, class B>
  void one_of(std::string_view name_a, const std::optional<A>& a, Range range_a, std::string_view name_b,
              const std::optional<B>& b, Range range_b) {
    if (a) check(key(name_a), *a, range_a);
    if (b) check(key(name_b), *b, range_b);
  }

 private:
  std::string key(std::string_view name) const { return path_ + "." + std::string(name); }
  std::string path_;
};

// ---- the key lister: every key's dotted path ------------------------------

class KeyLister {
 public:
  template <class Body>
  void section(std::string_view name, Body&& body) {
    const std::size_t size = path_.size();
    path_ += std::string(name) + ".";
    body();
    path_.resize(size);
  }
  template <class T, class C>
  void field(std::string_view name, const T&, const C&) {
    keys_.push_back(path_ + std::string(name));
  }
  template <class A, class B>
  void one_of(std::string_view name_a, const A&, Range, std::string_view name_b, const B&, Range) {
    keys_.push_back(path_ + std::string(name_a));
    keys_.push_back(path_ + std::string(name_b));
  }
  std::vector<std::string> keys() && { return std::move(keys_); }

 private:
  std::string path_;
  std::vector<std::string> keys_;
};

// ---- the reader: YAML tree -> struct ------------------------------------------

std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      return "\"" + node.Scalar() + "\"";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a mapping";
    default:
      return "nothing";
  }
}

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

class Reader {
 public:
  explicit Reader(const YAML::Node& root) { enter(root, ""); }

  // Called once the schema has been walked: reports keys the schema does not know.
  void finish() { leave(); }

  template <class Body>
  void section(std::string_view name, Body&& body) {
    const YAML::Node* node = take(name);
    if (node == nullptr) return;  // absent: all defaults
    const std::string path = key(name);
    if (!node->IsMap()) fail(fmt::format("{}: expected a mapping of keys, got {}", path, describe(*node)));
    enter(*node, path);
    body();
    leave();
  }

  template <class T, class C>
  void field(std::string_view name, T& value, const C& constraint) {
    const YAML::Node* node = take(name);
    if (node == nullptr) return;
    const std::string path = key(name);
    parse(path, *node, value, constraint);
    check(path, value, constraint);
  }

  // Two alternative keys: a file that gives either replaces the default; both is an error.
  template <class A, class B>
  void one_of(std::string_view name_a, std::optional<A>& a, Range range_a, std::string_view name_b, std::optional<B>& b,
              Range range_b) {
    const YAML::Node* node_a = take(name_a);
    const YAML::Node* node_b = take(name_b);
    if (node_a && node_b) fail(fmt::format("{}: give either {} or {}, not both", frames_.back().path, name_a, name_b));
    if (node_a) {
      A parsed{};
      parse(key(name_a), *node_a, parsed, range_a);
      check(key(name_a), parsed, range_a);
      a = parsed;
      b.reset();
    }
    if (node_b) {
      B parsed{};
      parse(key(name_b), *node_b, parsed, range_b);
      check(key(name_b), parsed, range_b);
      b = parsed;
      a.reset();
    }
  }

 private:
  struct Entry {
    std::string key;
    YAML::Node value;
    bool used = false;
  };
  struct Frame {
    std::string path;
    std::vector<Entry> entries;
    std::vector<std::string> known;  // keys the schema asked for here, for the unknown-key message
  };

  void enter(const YAML::Node& node, std::string path) {
    Frame frame{std::move(path), {}, {}};
    if (node.IsMap()) {
      for (const auto& item : node) {
        const std::string k = item.first.IsScalar() ? item.first.Scalar() : describe(item.first);
        for (const Entry& e : frame.entries)
          if (e.key == k) fail(fmt::format("{}: duplicate key", join(frame.path, k)));
        frame.entries.push_back({k, item.second, false});
      }
    }
    frames_.push_back(std::move(frame));
  }

  void leave() {
    const Frame& frame = frames_.back();
    for (const Entry& e : frame.entries)
      if (!e.used)
        fail(fmt::format("{}: unknown key (known here: {})", join(frame.path, e.key), fmt::join(frame.known, ", ")));
    frames_.pop_back();
  }

  // Records the key as known at this level and returns its node, or nullptr when absent.
  const YAML::Node* take(std::string_view name) {
    Frame& frame = frames_.back();
    frame.known.emplace_back(name);
    for (Entry& e : frame.entries) {
      if (e.key == name) {
        e.used = true;
        return &e.value;
      }
    }
    return nullptr;
  }

  std::string key(std::string_view name) const { return join(frames_.back().path, name); }
  static std::string join(const std::string& path, std::string_view name) {
    return path.empty() ? std::string(name) : path + "." + std::string(name);
  }

  static const std::string& scalar(const std::string& path, const YAML::Node& node, std::string_view expected) {
    if (!node.IsScalar()) fail(fmt::format("{}: expected {}, got {}", path, expected, describe(node)));
    return node.Scalar();
  }

  static void parse(const std::string& path, const YAML::Node& node, double& value, Range) {
    const std::string& text = scalar(path, node, "a number");
    const char* end = text.data() + text.size();
    const char* begin = text.data() + (!text.empty() && text[0] == '+' ? 1 : 0);
    auto [ptr, ec] = std::from_chars(begin, end, value);
    if (ec != std::errc() || ptr != end || text.empty())
      fail(fmt::format("{}: expected a number, got {}", path, describe(node)));
  }
  template <class C>
  static void parse(const std::string& path, const YAML::Node& node, int& value, C) {
    const std::string& text = scalar(path, node, "an integer");
    const char* end = text.data() + text.size();
    const char* begin = text.data() + (!text.empty() && text[0] == '+' ? 1 : 0);
    long long parsed = 0;
    auto [ptr, ec] = std::from_chars(begin, end, parsed);
    if (ec == std::errc::result_out_of_range ||
        (ec == std::errc() && ptr == end &&
         (parsed < std::numeric_limits<int>::min() || parsed > std::numeric_limits<int>::max())))
      fail(fmt::format("{}: {} is out of range", path, text));
    if (ec != std::errc() || ptr != end || text.empty())
      fail(fmt::format("{}: expected an integer, got {}", path, describe(node)));
    value = static_cast<int>(parsed);
  }
  static void parse(const std::string& path, const YAML::Node& node, bool& value, AnyText) {
    const std::string& text = scalar(path, node, "true or false");
    if (iequals(text, "true")) {
      value = true;
    } else if (iequals(text, "false")) {
      value = false;
    } else {
      fail(fmt::format("{}: expected true or false, got {}", path, describe(node)));
    }
  }
  template <class C>
  static void parse(const std::string& path, const YAML::Node& node, std::string& value, C) {
    if (node.IsNull()) {  // "key:" with nothing after it
      value.clear();
      return;
    }
    value = scalar(path, node, "a string");
  }
  template <class E>
  static void parse(const std::string& path, const YAML::Node& node, E& value, Choice<E> choice) {
    const std::string& text = scalar(path, node, "a name");
    for (const auto& [name, e] : choice.names) {
      if (iequals(name, text)) {
        value = e;
        return;
      }
    }
    std::vector<std::string_view> names;
    for (const auto& [name, e] : choice.names) names.push_back(name);
    fail(fmt::format("{}: {} is not one of {}", path, describe(node), fmt::join(names, ", ")));
  }
  template <std::size_t N>
  static void parse(const std::string& path, const YAML::Node& node, std::array<double, N>& values, Range r) {
    if (!node.IsSequence() || node.size() != N)
      fail(fmt::format("{}: expected a list of {} numbers, got {}", path, N,
                       node.IsSequence() ? fmt::format("{} values", node.size()) : describe(node)));
    for (std::size_t i = 0; i < N; ++i) parse(fmt::format("{}[{}]", path, i), node[i], values[i], r);
  }
  static void parse(const std::string& path, const YAML::Node& node, std::vector<double>& values, Angles a) {
    if (!node.IsSequence()) fail(fmt::format("{}: expected a list of numbers, got {}", path, describe(node)));
    values.assign(node.size(), 0.0);
    for (std::size_t i = 0; i < values.size(); ++i) parse(fmt::format("{}[{}]", path, i), node[i], values[i], a.range);
  }

  std::vector<Frame> frames_;
};

// ---- the writer: struct -> YAML text ------------------------------------------

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    const auto u = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (u < 0x20 || u == 0x7F) {
      out += fmt::format("\\x{:02X}", u);
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

template <class E>
std::string_view name_of(E value, std::span<const std::pair<std::string_view, E>> names) {
  for (const auto& [name, e] : names)
    if (e == value) return name;
  return "?";
}

class Writer {
 public:
  template <class Body>
  void section(std::string_view name, Body&& body) {
    line(name, "");
    indent_ += 2;
    body();
    indent_ -= 2;
  }
  void field(std::string_view name, double value, Range) { line(name, number(value)); }
  template <class C>
  void field(std::string_view name, int value, C) {
    line(name, std::to_string(value));
  }
  void field(std::string_view name, bool value, AnyText) { line(name, value ? "true" : "false"); }
  template <class C>
  void field(std::string_view name, const std::string& value, C) {
    line(name, quoted(value));
  }
  template <class E>
  void field(std::string_view name, E value, Choice<E> choice) {
    line(name, name_of(value, choice.names));
  }
  template <std::size_t N>
  void field(std::string_view name, const std::array<double, N>& values, Range) {
    line(name, list(values));
  }
  void field(std::string_view name, const std::vector<double>& values, Angles) { line(name, list(values)); }
  template <class A, class B>
  void one_of(std::string_view name_a, const std::optional<A>& a, Range, std::string_view name_b,
              const std::optional<B>& b, Range) {
    if (a) line(name_a, list(*a));
    if (b) line(name_b, list(*b));
  }

  std::string text() const { return out_; }

 private:
  template <class Values>
  static std::string list(const Values& values) {
    std::vector<std::string> items;
    for (const double v : values) items.push_back(number(v));
    return fmt::format("[{}]", fmt::join(items, ", "));
  }
  void line(std::string_view name, std::string_view value) {
    out_ += fmt::format("{:{}}{}:{}{}\n", "", indent_, name, value.empty() ? "" : " ", value);
  }
  std::string out_;
  int indent_ = 0;
};

// ---- overrides: set on the YAML tree before reading, so they get the same checks --

void apply_override(YAML::Node& root, const ConfigOverride& o) {
  std::vector<std::string> parts;
  std::stringstream stream(o.key);
  for (std::string part; std::getline(stream, part, '.');) {
    if (part.empty()) fail(fmt::format("{}: not a key path (like registration.model)", o.key));
    parts.push_back(part);
  }
  if (parts.empty()) fail("empty key path in a configuration override");
  // yaml-cpp's Node::operator= writes through to the referenced node; reset() rebinds.
  YAML::Node node;
  node.reset(root);
  std::string path;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    path += (i ? "." : "") + parts[i];
    YAML::Node child = node[parts[i]];
    if (!child.IsDefined() || child.IsNull()) {
      node[parts[i]] = YAML::Node(YAML::NodeType::Map);
      child.reset(node[parts[i]]);
    }
    if (!child.IsMap()) fail(fmt::format("{}: expected a mapping of keys, got {}", path, describe(child)));
    node.reset(child);
  }
  // A list (translation_m=[0.02,0,-0.08]) is YAML flow syntax; anything else
  // stays text, as a scalar in the file would be.
  if (!o.value.empty() && o.value.front() == '[') {
    try {
      node[parts.back()] = YAML::Load(o.value);
    } catch (const YAML::Exception& e) {
      fail(fmt::format("{}: {} is not a YAML list ({})", o.key, o.value, e.msg));
    }
  } else {
    node[parts.back()] = o.value;
  }
}

DaemonConfig read(YAML::Node root, std::string_view source_name, std::span<const ConfigOverride> overrides) {
  if (!root.IsDefined() || root.IsNull()) root.reset(YAML::Node(YAML::NodeType::Map));
  if (!root.IsMap())
    fail(fmt::format("{}: expected a mapping of sections (lidar, imu, ...), got {}", source_name, describe(root)));
  for (const ConfigOverride& o : overrides) apply_override(root, o);
  DaemonConfig config;
  Reader reader(root);
  visit_config(reader, config);
  reader.finish();
  check_consistency(config);
  return config;
}

}  // namespace

DaemonConfig load_config(std::string_view yaml_text, std::string_view source_name,
                         std::span<const ConfigOverride> overrides) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml_text));
  } catch (const YAML::Exception& e) {
    if (e.mark.is_null()) fail(fmt::format("{}: YAML error: {}", source_name, e.msg));
    fail(fmt::format("{}:{}:{}: YAML syntax error: {}", source_name, e.mark.line + 1, e.mark.column + 1, e.msg));
  }
  return read(root, source_name, overrides);
}

DaemonConfig load_config_file(const std::string& path, std::span<const ConfigOverride> overrides) {
  std::ifstream file(path, std::ios::binary);
  if (!file) fail(fmt::format("{}: cannot open the configuration file", path));
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) fail(fmt::format("{}: cannot read the configuration file", path));
  return load_config(text.str(), path, overrides);
}

DaemonConfig default_config(std::span<const ConfigOverride> overrides) {
  return read(YAML::Node(YAML::NodeType::Map), "defaults", overrides);
}

std::string to_yaml(const DaemonConfig& config) {
  Writer writer;
  visit_config(writer, config);
  return writer.text();
}

std::vector<std::string> config_keys() {
  KeyLister lister;
  const DaemonConfig defaults;
  visit_config(lister, defaults);
  return std::move(lister).keys();
}

void validate(const DaemonConfig& config) {
  Checker checker;
  visit_config(checker, config);
  check_consistency(config);
}

std::string_view to_string(WeightModel model) { return name_of<WeightModel>(model, kModels); }
std::string_view to_string(LogLevel level) { return name_of<LogLevel>(level, kLogLevels); }

Eigen::Isometry3d extrinsic_T_LI(const ExtrinsicConfig& extrinsic) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  if (extrinsic.rotation_quaternion_wxyz) {
    const auto& w = *extrinsic.rotation_quaternion_wxyz;
    q = Eigen::Quaterniond(w[0], w[1], w[2], w[3]).normalized();
  } else if (extrinsic.rotation_rpy_deg) {
    const auto& rpy = *extrinsic.rotation_rpy_deg;
    constexpr double kDeg = std::numbers::pi / 180.0;
    q = Eigen::AngleAxisd(rpy[2] * kDeg, Eigen::Vector3d::UnitZ()) *
        Eigen::AngleAxisd(rpy[1] * kDeg, Eigen::Vector3d::UnitY()) *
        Eigen::AngleAxisd(rpy[0] * kDeg, Eigen::Vector3d::UnitX());
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = Eigen::Vector3d(extrinsic.translation_m[0], extrinsic.translation_m[1], extrinsic.translation_m[2]);
  return T;
}

}  // namespace tumble::daemon
