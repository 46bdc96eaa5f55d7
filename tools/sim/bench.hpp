// The paper's bench (§IV-V) in software: rail runs and turntable runs over a
// range of speeds in both directions (to calibrate the speed-uncertainty
// models) and 46 rolling-cage runs, all with one lidar unit and a static
// start. Deterministic for a seed.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace tumble::sim {

inline constexpr int kBenchCageRuns = 46;
inline constexpr int kBenchLongRunsPerScene = 4;  // realistic bench: garage, corridor, yard
inline constexpr int kBenchPeopleCages = 3;       // realistic bench: cage runs, each without and with people
inline constexpr int kBenchHallRuns = 2;          // realistic bench: long cage runs in the glass-ended hall, last
inline constexpr double kBenchStaticStartS = 1.5;

struct BenchRun {
  std::string name;       // also its folder
  std::string kind;       // rail, turntable, rolling_cage; realistic bench also long, people
  double nominal_speed = 0.0;  // signed: m/s along the rail, rad/s about the table axis, cage roll rate
  std::string speed_unit;      // m/s or rad/s
  YAML::Node scenario;    // a complete scenario document
};

struct BenchOptions {
  std::uint64_t seed = 1;
  int jobs = 1;
  int max_runs = 0;            // > 0: only the first max_runs of the plan
  double max_duration_s = 0.0;  // > 0: cut every run to at most this long (quick looks, tests)
  bool realistic = false;       // the plan came from plan_realistic_bench (recorded in bench.yaml)
};

std::vector<BenchRun> plan_bench(std::uint64_t seed);

// bench2: the same rail, turntable and cage runs with every sensor
// error source of tumble-sim on at its datasheet magnitude, the rig's
// uncalibrated lidar-IMU time offset, the cage's bars in the lidar's view,
// and long out-and-back runs (>= 60 s, >= 50 m) in the garage, the corridor
// and the yard; then same-seed sets of cage runs that differ only in their
// people (none, walkers, the rope puller, both; kind people).
std::vector<BenchRun> plan_realistic_bench(std::uint64_t seed);

// The rig's constant lidar-IMU time offset in a realistic bench: a few ms
// either way, what an uncalibrated rig has (the same for all its runs).
double realistic_rig_imu_time_offset_s(std::uint64_t seed);

// Writes every run into out/<name>/ (scenario.yaml + the run's files), then
// bench.yaml and bench.csv indexing them. Progress lines go to `progress`.
void write_bench(const std::vector<BenchRun>& plan, const std::filesystem::path& out, const BenchOptions& options,
                 std::ostream& progress);

}  // namespace tumble::sim
