#include "tools/sim/motion_load.hpp"

#include "core/angles.hpp"
#include "tools/sim/motion_compose.hpp"
#include "tools/sim/motion_primitives.hpp"
#include "tools/sim/motion_rolling_cage.hpp"
#include "tools/sim/motion_walk.hpp"
#include "tools/sim/profile_load.hpp"
#include "tools/sim/yaml_fields.hpp"

#include <filesystem>
#include <numbers>
#include <stdexcept>

namespace tumble::sim {

namespace {


// {xyz_m: [...], rpy_deg: [...]}, both optional inside.
Eigen::Isometry3d read_pose(const YAML::Node& map, const YamlPath& at, std::string_view key) {
  if (!has_key(map, key)) return Eigen::Isometry3d::Identity();
  const YAML::Node n = map[std::string(key)];
  const YamlPath here = at.key(key);
  check_keys(n, here, {"xyz_m", "rpy_deg"});
  return pose_from_xyz_rpy_deg(read_vec3(n, here, "xyz_m", Eigen::Vector3d::Zero()),
                               read_vec3(n, here, "rpy_deg", Eigen::Vector3d::Zero()));
}

Eigen::Vector3d read_axis(const YAML::Node& map, const YamlPath& at, const Eigen::Vector3d& fallback) {
  const Eigen::Vector3d axis = read_vec3(map, at, "axis", fallback);
  if (!(axis.norm() > 1e-9)) at.key("axis").fail("must be a nonzero vector");
  return axis.normalized();
}

YAML::Node required_node(const YAML::Node& map, const YamlPath& at, std::string_view key) {
  const YAML::Node n = map[std::string(key)];
  if (!n) at.key(key).fail("missing");
  return n;
}

class Loader {
 public:
  explicit Loader(const MotionLoadOptions& options) : options_(options) {}

  std::unique_ptr<Motion> motion(const YAML::Node& node, const YamlPath& at) {
    require_map(node, at);
    const std::string type = read_string(node, at, "type");
    std::unique_ptr<Motion> m;
    if (type == "static") {
      check_keys(node, at, {"type", "description", "origin", "duration_s"});
      m = std::make_unique<StaticMotion>(read_positive(node, at, "duration_s"));
    } else if (type == "rail") {
      check_keys(node, at, {"type", "description", "origin", "mount", "axis", "profile"});
      m = std::make_unique<RailMotion>(read_axis(node, at, Eigen::Vector3d::UnitX()),
                                       read_profile(node["profile"], at.key("profile"), ProfileUnits::Linear),
                                       read_pose(node, at, "mount"));
    } else if (type == "turntable") {
      check_keys(node, at, {"type", "description", "origin", "mount", "axis", "profile"});
      m = std::make_unique<TurntableMotion>(read_axis(node, at, Eigen::Vector3d::UnitZ()),
                                            read_profile(node["profile"], at.key("profile"), ProfileUnits::Angular),
                                            read_pose(node, at, "mount"));
    } else if (type == "rolling_cage") {
      m = rolling_cage(node, at);
    } else if (type == "walk") {
      m = walk(node, at);
    } else if (type == "vibration") {
      m = vibration(node, at);
    } else if (type == "sequence") {
      m = sequence(node, at);
    } else if (type == "superpose") {
      check_keys(node, at, {"type", "description", "origin", "base", "offset"});
      m = std::make_unique<SuperposedMotion>(motion(required_node(node, at, "base"), at.key("base")),
                                             motion(required_node(node, at, "offset"), at.key("offset")));
    } else {
      at.key("type").fail(
          "must be one of: static, rail, turntable, rolling_cage, walk, vibration, sequence, superpose (got '" + type +
          "')");
    }
    if (!has_key(node, "origin")) return m;
    return std::make_unique<PlacedMotion>(read_pose(node, at, "origin"), std::move(m));
  }

 private:
  std::unique_ptr<Motion> rolling_cage(const YAML::Node& node, const YamlPath& at) {
    check_keys(node, at,
               {"type", "description", "origin", "mount", "radius_m", "roll", "seed", "bounces", "jolts", "min_gap_s"});
    RollingCageParams params;
    params.radius_m = read_positive(node, at, "radius_m");
    params.roll_rad = read_profile(node["roll"], at.key("roll"), ProfileUnits::Angular);
    params.mount = read_pose(node, at, "mount");
    CageEventRanges ranges;
    ranges.min_gap_s = read_non_negative(node, at, "min_gap_s", ranges.min_gap_s);
    if (has_key(node, "bounces")) {
      const YAML::Node b = node["bounces"];
      const YamlPath here = at.key("bounces");
      check_keys(b, here, {"count", "height_m", "peak_m_s2"});
      ranges.bounce_count = read_count(b, here, "count", 0);
      std::tie(ranges.bounce_height_min_m, ranges.bounce_height_max_m) =
          read_positive_range(b, here, "height_m", {ranges.bounce_height_min_m, ranges.bounce_height_max_m});
      std::tie(ranges.bounce_peak_min_m_s2, ranges.bounce_peak_max_m_s2) =
          read_positive_range(b, here, "peak_m_s2", {ranges.bounce_peak_min_m_s2, ranges.bounce_peak_max_m_s2});
      if (!(ranges.bounce_peak_min_m_s2 > kStandardGravity_m_s2))
        here.key("peak_m_s2").fail("must exceed g = 9.80665 m/s^2 (an impact has to lift the cage)");
    }
    if (has_key(node, "jolts")) {
      const YAML::Node j = node["jolts"];
      const YamlPath here = at.key("jolts");
      check_keys(j, here, {"count", "swing_rad_s", "peak_rad_s2"});
      ranges.jolt_count = read_count(j, here, "count", 0);
      std::tie(ranges.jolt_swing_min_rad_s, ranges.jolt_swing_max_rad_s) =
          read_positive_range(j, here, "swing_rad_s", {ranges.jolt_swing_min_rad_s, ranges.jolt_swing_max_rad_s});
      std::tie(ranges.jolt_peak_min_rad_s2, ranges.jolt_peak_max_rad_s2) =
          read_positive_range(j, here, "peak_rad_s2", {ranges.jolt_peak_min_rad_s2, ranges.jolt_peak_max_rad_s2});
    }
    const std::uint64_t seed = options_.seed ? *options_.seed : read_seed(node, at, "seed", 0);
    try {
      place_cage_events(params, ranges, seed);
    } catch (const CageEventsDoNotFit& e) {
      at.key(e.key).fail(e.what());
    }
    return std::make_unique<RollingCageMotion>(std::move(params));
  }

  std::unique_ptr<Motion> walk(const YAML::Node& node, const YamlPath& at) {
    check_keys(node, at,
               {"type", "description", "origin", "mount", "forward", "step_frequency_hz", "bob_m", "sway_m",
                "yaw_sway_deg", "pitch_bob_deg", "roll_sway_deg"});
    WalkParams p;
    p.forward_m = read_profile(node["forward"], at.key("forward"), ProfileUnits::Linear);
    p.step_frequency_hz = read_positive(node, at, "step_frequency_hz", p.step_frequency_hz);
    p.bob_m = read_non_negative(node, at, "bob_m", p.bob_m);
    p.sway_m = read_non_negative(node, at, "sway_m", p.sway_m);
    p.yaw_sway_rad = read_non_negative(node, at, "yaw_sway_deg", p.yaw_sway_rad / kDegToRad) * kDegToRad;
    p.pitch_bob_rad = read_non_negative(node, at, "pitch_bob_deg", p.pitch_bob_rad / kDegToRad) * kDegToRad;
    p.roll_sway_rad = read_non_negative(node, at, "roll_sway_deg", p.roll_sway_rad / kDegToRad) * kDegToRad;
    p.mount = read_pose(node, at, "mount");
    return std::make_unique<WalkMotion>(std::move(p));
  }

  std::unique_ptr<Motion> vibration(const YAML::Node& node, const YamlPath& at) {
    check_keys(node, at,
               {"type", "description", "origin", "duration_s", "frequency_hz", "translation_m", "rotation_deg",
                "fade_s"});
    VibrationParams p;
    p.duration_s = read_positive(node, at, "duration_s");
    p.frequency_hz = read_positive(node, at, "frequency_hz");
    p.translation_m = read_vec3(node, at, "translation_m", Eigen::Vector3d::Zero());
    p.rotation_rad = read_vec3(node, at, "rotation_deg", Eigen::Vector3d::Zero()) * kDegToRad;
    p.fade_s = read_non_negative(node, at, "fade_s", std::min(p.fade_s, p.duration_s / 2));
    if (2.0 * p.fade_s > p.duration_s) at.key("fade_s").fail("must be at most duration_s / 2");
    return std::make_unique<VibrationMotion>(p);
  }

  std::unique_ptr<Motion> sequence(const YAML::Node& node, const YamlPath& at) {
    check_keys(node, at, {"type", "description", "origin", "parts"});
    const YAML::Node parts = node["parts"];
    const YamlPath parts_at = at.key("parts");
    if (!parts || !parts.IsSequence() || parts.size() == 0) parts_at.fail("must be a non-empty list of motions");
    std::vector<std::unique_ptr<Motion>> loaded;
    for (std::size_t i = 0; i < parts.size(); ++i) {
      if (i > 0 && parts[i].IsMap() && has_key(parts[i], "origin"))
        parts_at.index(i).key("origin").fail("only the first part can be placed; later parts continue from the previous one");
      loaded.push_back(motion(parts[i], parts_at.index(i)));
    }
    try {
      return std::make_unique<SequenceMotion>(std::move(loaded));
    } catch (const std::invalid_argument& e) {
      parts_at.fail(e.what());
    }
  }

  const MotionLoadOptions& options_;
};

}  // namespace

std::unique_ptr<Motion> load_motion(const YAML::Node& node, const MotionLoadOptions& options) {
  return Loader(options).motion(node, YamlPath{options.source_name, options.key_path});
}

std::unique_ptr<Motion> load_motion(const YAML::Node& node) { return load_motion(node, MotionLoadOptions{}); }

std::unique_ptr<Motion> load_motion_file(const std::string& yaml_path, std::optional<std::uint64_t> seed) {
  MotionLoadOptions options;
  options.source_name = std::filesystem::path(yaml_path).filename().string();
  options.seed = seed;
  return load_motion(load_yaml_file(yaml_path), options);
}

}  // namespace tumble::sim
