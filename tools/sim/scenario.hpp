// A scenario: which scene, which motion, how the two sensors are set up and
// mounted, the seed and the duration (format: tools/sim/README.md). Every key
// is optional except scene and motion; errors name the file and the key.
#pragma once

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "tools/sim/imu_stream.hpp"
#include "tools/sim/lidar_stream.hpp"
#include "tools/sim/people.hpp"
#include "tools/sim/sim_config_error.hpp"

namespace tumble::sim {

struct Scenario {
  std::string source_name = "scenario";  // prefixes error messages
  std::string scene_ref;                 // as written: a name or a path
  std::filesystem::path scene_path;      // resolved
  std::string motion_ref;                // a name, a path, or "inline"
  YAML::Node motion;                     // the motion description itself
  std::optional<std::uint64_t> motion_seed;  // overrides the motion's own `seed:` keys (bench runs)
  std::uint64_t seed = 1;
  std::optional<double> duration_s;      // default: the motion's duration
  std::int64_t epoch_ns = 0;             // host (and synced lidar) clock at run time 0
  double ground_truth_rate_hz = 1000.0;
  Eigen::Isometry3d T_LI = Eigen::Isometry3d::Identity();  // IMU pose in the lidar frame
  double imu_time_offset_s = 0.0;  // tumbled's imu.imu_time_offset_s that cancels the IMU's timing error (ImuClock)

  LidarConfig lidar;
  LidarLinkConfig lidar_link;
  std::optional<std::uint64_t> lidar_unit_seed;  // default: the scenario seed
  std::optional<double> difop_phase_s;           // first DIFOP; default: random in [0, period)

  ImuConfig imu;
  ImuLinkConfig imu_link;
  bool imu_noise = true;                         // false: ideal readings (still clipped)
  std::optional<double> imu_clock_drift_ppm;     // default: random in [-10, 10]
  std::optional<double> imu_sample_time_start_s;  // SampleTimeFine of the first sample; default: random

  PeopleConfig people;  // walkers and the rope puller, each off unless its section is present
};

// Where named scenes, motions and scenarios live (the source tree).
std::filesystem::path sim_data_dir(const std::string& kind);  // "scenes", "motions", "scenarios"

// The scenario `./tumble demo` runs: a rolling-cage run in the garage.
std::filesystem::path default_scenario_path();

// Throws SimConfigError("file: key: why").
Scenario load_scenario(const std::filesystem::path& path);
// base_dir resolves relative scene and motion paths.
Scenario parse_scenario(const YAML::Node& root, const std::string& source_name, const std::filesystem::path& base_dir);

// The scenario as YAML, with every value resolved (for manifests and benches).
YAML::Node scenario_to_yaml(const Scenario& s);

std::string format_utc(std::int64_t t_ns);  // "2021-05-26T12:00:00.000000Z"
const char* number_format_key(mti::NumberFormat f);

}  // namespace tumble::sim
