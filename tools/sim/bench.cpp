#include "tools/sim/bench.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <mutex>
#include <numbers>
#include <thread>

#include "tools/sim/run_writer.hpp"
#include "tools/sim/scenario.hpp"
#include "tools/sim/sensor_rng.hpp"

namespace tumble::sim {
namespace {

namespace fs = std::filesystem;

// Everything happens in the garage's clear middle lane (|y| < 4 m along x,
// scenes/garage.yaml): the rail along it, the turntable at its centre, the
// cage rolling across the centre.
constexpr const char* kBenchScene = "garage";
constexpr double kRailLengthM = 24.0;    // usable travel of the carriage, centred on x = 0
constexpr double kRailHeightM = 1.0;     // lidar above the floor
constexpr double kCageMaxRollM = 14.0;   // rolls from x = -+7 m to about +-7 m
constexpr double kCageMaxYawDeg = 10.0;  // heading spread: stays inside the lane
constexpr double kCageRadiusM = 0.3;     // 11 rad/s is then 3.3 m/s, as in the paper
constexpr int kBenchWalkers = 4;         // people crossing the lane in the realistic bench's people runs

constexpr double kRailSpeedsMS[] = {0.25, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5};
constexpr double kTurntableRatesRadS[] = {0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 11.0};

YAML::Node flow(std::initializer_list<double> v) {
  YAML::Node n = YAML::Node(std::vector<double>(v));
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

YAML::Node pose(std::initializer_list<double> xyz, std::initializer_list<double> rpy = {0, 0, 0}) {
  YAML::Node n;
  n["xyz_m"] = flow(xyz);
  n["rpy_deg"] = flow(rpy);
  return n;
}

YAML::Node step(const char* kind, YAML::Node body) {
  YAML::Node n;
  n[kind] = body;
  return n;
}

YAML::Node hold(double s) {
  YAML::Node n;
  n["hold_s"] = s;
  return n;
}

YAML::Node ramp(double to_rate, double peak_accel, bool angular) {
  YAML::Node b;
  b[angular ? "to_rad_s" : "to_m_s"] = to_rate;
  b[angular ? "peak_rad_s2" : "peak_m_s2"] = peak_accel;
  return step("ramp", b);
}

YAML::Node scenario_node(const char* scene, YAML::Node motion, std::uint64_t run_seed, std::uint64_t bench_seed,
                         int index) {
  YAML::Node s;
  s["scene"] = scene;
  s["motion"] = motion;
  s["seed"] = run_seed;
  // One minute apart on the clock, like runs recorded one after another.
  s["epoch_utc"] = format_utc((1'622'030'400LL + 60LL * index) * 1'000'000'000LL).substr(0, 19) + "Z";
  s["lidar"]["unit_seed"] = bench_seed;  // one physical lidar for the whole bench
  return s;
}

BenchRun rail_run(SensorRng& rng, double speed_m_s, int index, std::uint64_t bench_seed) {
  const double v = std::abs(speed_m_s);
  // Gentle to brisk, but always reaching the nominal speed with half the rail
  // left to cruise (each raised-cosine ramp covers v^2 / a).
  const double peak_accel = rng.uniform(std::max(0.5, 4.0 * v * v / kRailLengthM), 3.0);
  // About 8 s at speed, as far as the rail allows.
  const double distance = std::min(kRailLengthM, v * 8.0 + 2.0 * v * v / peak_accel);
  const double sign = speed_m_s < 0 ? -1.0 : 1.0;
  YAML::Node travel;
  travel["distance_m"] = sign * distance;
  travel["max_m_s"] = v;
  travel["peak_m_s2"] = peak_accel;
  YAML::Node m;
  m["type"] = "rail";
  m["origin"] = pose({-sign * kRailLengthM / 2, 0.0, kRailHeightM});
  m["axis"] = flow({1, 0, 0});
  m["profile"].push_back(hold(kBenchStaticStartS));
  m["profile"].push_back(step("travel", travel));
  m["profile"].push_back(hold(1.0));
  char name[64];
  std::snprintf(name, sizeof name, "rail-%02d-%s%.2fmps", index, sign > 0 ? "fwd-" : "back-", std::abs(speed_m_s));
  return {name, "rail", speed_m_s, "m/s", scenario_node(kBenchScene, m, rng.next_u64(), bench_seed, index)};
}

BenchRun turntable_run(SensorRng& rng, double rate_rad_s, int index, std::uint64_t bench_seed) {
  const double peak_accel = rng.uniform(5.0, 20.0);
  YAML::Node m;
  m["type"] = "turntable";
  m["origin"] = pose({0.0, 0.0, 0.8});
  m["axis"] = flow({0, 0, 1});
  // Off the axis, as a sensor head on a real table: centripetal acceleration too.
  m["mount"] = pose({0.1, 0.0, 0.25});
  m["profile"].push_back(hold(kBenchStaticStartS));
  m["profile"].push_back(ramp(rate_rad_s, peak_accel, true));
  m["profile"].push_back(hold(3.0));
  m["profile"].push_back(ramp(0.0, peak_accel, true));
  m["profile"].push_back(hold(0.5));
  char name[64];
  std::snprintf(name, sizeof name, "turntable-%02d-%s%.1fradps", index, rate_rad_s > 0 ? "ccw-" : "cw-",
                std::abs(rate_rad_s));
  return {name, "turntable", rate_rad_s, "rad/s", scenario_node(kBenchScene, m, rng.next_u64(), bench_seed, index)};
}

BenchRun cage_run(SensorRng& rng, int cage_index, int index, std::uint64_t bench_seed) {
  const double rate = rng.uniform(3.0, 11.0) * (rng.chance(0.5) ? 1.0 : -1.0);
  const double pull_accel = rng.uniform(10.0, 40.0);
  const double ramp_s = 2.0 * std::abs(rate) / pull_accel;
  // Roll as long as the floor allows (at least 2 s at speed for the events).
  const double hold_s = std::clamp(kCageMaxRollM / (std::abs(rate) * kCageRadiusM) - ramp_s, 2.0, 6.0);
  YAML::Node m;
  m["type"] = "rolling_cage";
  const double direction = rate > 0 ? 1.0 : -1.0;  // positive roll rolls along +x
  m["origin"] = pose({-direction * kCageMaxRollM / 2, 0.0, 0.0}, {0.0, 0.0, rng.uniform(-kCageMaxYawDeg, kCageMaxYawDeg)});
  m["radius_m"] = kCageRadiusM;
  m["mount"] = pose({0.0, 0.0, 0.05});
  m["roll"].push_back(hold(kBenchStaticStartS));
  m["roll"].push_back(ramp(rate, pull_accel, true));
  m["roll"].push_back(hold(hold_s));
  m["roll"].push_back(ramp(0.0, pull_accel, true));
  m["roll"].push_back(hold(0.5));
  m["seed"] = rng.next_u64() >> 1;
  YAML::Node bounces;
  bounces["count"] = static_cast<int>(rng.uniform(0.0, 4.0));
  bounces["height_m"] = flow({0.02, 0.1});
  bounces["peak_m_s2"] = flow({100.0, 200.0});
  m["bounces"] = bounces;
  YAML::Node jolts;
  jolts["count"] = static_cast<int>(rng.uniform(0.0, 4.0));
  jolts["swing_rad_s"] = flow({0.2, 1.0});
  jolts["peak_rad_s2"] = flow({300.0, 800.0});
  m["jolts"] = jolts;
  char name[64];
  std::snprintf(name, sizeof name, "cage-%02d", cage_index);
  return {name, "rolling_cage", rate, "rad/s", scenario_node(kBenchScene, m, rng.next_u64(), bench_seed, index)};
}

// Every error source of the sensor models on at its default (datasheet) magnitude.
void turn_on_error_sources(YAML::Node& scenario, double imu_time_offset_s, bool in_cage) {
  for (const char* key : {"scale_factor_error", "misalignment", "g_sensitivity", "temperature_drift", "timestamp_jitter"})
    scenario["imu"][key] = true;
  for (const char* key : {"range_offset_error", "intensity_range_bias", "dark_surface_dropout"}) scenario["lidar"][key] = true;
  if (in_cage) {
    // The lidar sits 5 cm above the cage's centre (cage_run's mount), its
    // roll axis along y.
    YAML::Node bars;
    bars["cage_radius_m"] = kCageRadiusM;
    bars["centre_m"] = flow({0.0, 0.0, -0.05});
    scenario["lidar"]["cage_bars"] = bars;
  }
  scenario["extrinsics"]["imu_time_offset_s"] = imu_time_offset_s;
}

// Scenes and out-and-back routes for the long runs: start, heading and the
// way out along it, all in the clear (garage lane, corridor, the yard's open
// strip at y = 10 m between the light poles).
// The corridor's walls are 1.2 m either side: straight down it.
struct LongRoute {
  const char* scene;
  double x_m, y_m, max_out_m, max_yaw_deg;
};
constexpr LongRoute kLongRoutes[] = {
    {"garage", -14.0, 0.0, 28.0, 3.0}, {"corridor", -20.0, 0.0, 40.0, 0.0}, {"yard", -15.0, 10.0, 28.0, 3.0}};
// Down the middle of the hall (scenes/hall.yaml), between its glass ends.
constexpr LongRoute kHallRoute = {"hall", -13.0, 0.0, 26.0, 2.0};

// The cage pulled out and rolled back to where it started, with bounces and
// jolts all the way: >= 50 m and >= 60 s at <= 0.9 m/s.
YAML::Node long_cage_motion(SensorRng& rng, const LongRoute& route, double& rate) {
  rate = rng.uniform(2.5, 3.0);
  const double out_m = rng.uniform(26.0, route.max_out_m);
  const double pull_accel = rng.uniform(5.0, 15.0);
  // A raised-cosine ramp between rest and the rate covers rate^2 / accel of
  // roll angle, and so does each half of the reversal: hold for the rest.
  const double hold_s = (out_m / kCageRadiusM - 2.0 * rate * rate / pull_accel) / rate;
  YAML::Node m;
  m["type"] = "rolling_cage";
  m["origin"] = pose({route.x_m, route.y_m, 0.0}, {0.0, 0.0, rng.uniform(-route.max_yaw_deg, route.max_yaw_deg)});
  m["radius_m"] = kCageRadiusM;
  m["mount"] = pose({0.0, 0.0, 0.05});
  m["roll"].push_back(hold(kBenchStaticStartS));
  m["roll"].push_back(ramp(rate, pull_accel, true));
  m["roll"].push_back(hold(hold_s));
  m["roll"].push_back(ramp(-rate, pull_accel, true));
  m["roll"].push_back(hold(hold_s));
  m["roll"].push_back(ramp(0.0, pull_accel, true));
  m["roll"].push_back(hold(1.0));
  m["seed"] = rng.next_u64() >> 1;
  m["min_gap_s"] = 0.5;
  YAML::Node bounces;
  bounces["count"] = static_cast<int>(rng.uniform(4.0, 9.0));
  bounces["height_m"] = flow({0.02, 0.1});
  bounces["peak_m_s2"] = flow({100.0, 200.0});
  m["bounces"] = bounces;
  YAML::Node jolts;
  jolts["count"] = static_cast<int>(rng.uniform(4.0, 9.0));
  jolts["swing_rad_s"] = flow({0.2, 1.0});
  jolts["peak_rad_s2"] = flow({300.0, 800.0});
  m["jolts"] = jolts;
  return m;
}

YAML::Node walk_leg(double distance_m, double speed_m_s, bool static_start, bool static_end) {
  YAML::Node travel;
  travel["distance_m"] = distance_m;
  travel["max_m_s"] = speed_m_s;
  travel["peak_m_s2"] = 0.8;
  YAML::Node leg;
  leg["type"] = "walk";
  if (static_start) leg["forward"].push_back(hold(kBenchStaticStartS));
  leg["forward"].push_back(step("travel", travel));
  if (static_end) leg["forward"].push_back(hold(1.0));
  return leg;
}

// Hand-held: walk out, turn around in place, walk back (>= 60 s at <= 1 m/s).
YAML::Node long_walk_motion(SensorRng& rng, const LongRoute& route, double& speed) {
  speed = rng.uniform(0.9, 1.0);
  const double out_m = rng.uniform(std::max(28.0, 31.0 * speed), route.max_out_m + 2.0);
  YAML::Node turn;
  turn["type"] = "turntable";
  YAML::Node about;
  about["angle_rad"] = std::numbers::pi;
  about["max_rad_s"] = 1.5;
  about["peak_rad_s2"] = 3.0;
  turn["profile"].push_back(step("travel", about));
  YAML::Node m;
  m["type"] = "sequence";
  m["origin"] = pose({route.x_m, route.y_m, 1.3}, {0.0, 0.0, rng.uniform(-route.max_yaw_deg, route.max_yaw_deg)});
  m["parts"].push_back(walk_leg(out_m, speed, true, false));
  m["parts"].push_back(turn);
  m["parts"].push_back(walk_leg(out_m, speed, false, true));
  return m;
}

struct RunResult {
  double duration_s = 0.0;
  std::string error;
};

void write_index(const std::vector<BenchRun>& plan, const std::vector<RunResult>& results, const fs::path& out,
                 const BenchOptions& options) {
  const std::uint64_t seed = options.seed;
  YAML::Node index;
  index["format"] = "tumble-sim bench 1";
  index["seed"] = seed;
  index["lidar_unit_seed"] = seed;
  index["static_start_s"] = kBenchStaticStartS;
  if (options.realistic) {
    index["error_sources"] = "all on at their default magnitudes (tools/sim/README.md)";
    index["imu_time_offset_s"] = realistic_rig_imu_time_offset_s(seed);
  }
  std::ofstream csv(out / "bench.csv");
  csv << "name,kind,nominal_speed,speed_unit,duration_s,dir\n";
  for (std::size_t i = 0; i < results.size(); ++i) {
    YAML::Node r;
    r["name"] = plan[i].name;
    r["kind"] = plan[i].kind;
    r["nominal_speed"] = plan[i].nominal_speed;
    r["speed_unit"] = plan[i].speed_unit;
    r["duration_s"] = results[i].duration_s;
    r["dir"] = plan[i].name;
    index["runs"].push_back(r);
    csv << plan[i].name << ',' << plan[i].kind << ',' << plan[i].nominal_speed << ',' << plan[i].speed_unit << ','
        << results[i].duration_s << ',' << plan[i].name << '\n';
  }
  std::ofstream yaml(out / "bench.yaml");
  yaml << YAML::Dump(index) << "\n";
  if (!csv || !yaml) throw std::runtime_error((out / "bench.yaml").string() + ": write failed");
}

}  // namespace

std::vector<BenchRun> plan_bench(std::uint64_t seed) {
  SensorRng rng(seed, "bench-plan");
  std::vector<BenchRun> plan;
  int index = 0;
  for (const double v : kRailSpeedsMS) {
    for (const double sign : {1.0, -1.0}) plan.push_back(rail_run(rng, sign * v, ++index, seed));
  }
  for (const double w : kTurntableRatesRadS) {
    for (const double sign : {1.0, -1.0}) plan.push_back(turntable_run(rng, sign * w, ++index, seed));
  }
  for (int c = 1; c <= kBenchCageRuns; ++c) plan.push_back(cage_run(rng, c, ++index, seed));
  return plan;
}

double realistic_rig_imu_time_offset_s(std::uint64_t seed) {
  SensorRng rng(seed, "bench-rig");
  const double magnitude_s = rng.uniform(0.002, 0.005);
  return rng.chance(0.5) ? magnitude_s : -magnitude_s;
}

std::vector<BenchRun> plan_realistic_bench(std::uint64_t seed) {
  // The same runs as plan_bench (its own random stream), then the errors on.
  std::vector<BenchRun> plan = plan_bench(seed);
  const double offset_s = realistic_rig_imu_time_offset_s(seed);
  for (BenchRun& run : plan) turn_on_error_sources(run.scenario, offset_s, run.kind == "rolling_cage");
  SensorRng rng(seed, "bench-long-runs");
  int index = static_cast<int>(plan.size());
  int long_index = 0;
  for (const LongRoute& route : kLongRoutes) {
    for (int k = 0; k < kBenchLongRunsPerScene; ++k) {
      const bool cage = k % 2 == 0;
      double nominal_speed = 0.0;  // the cage's roll rate out, the walker's speed
      YAML::Node motion = cage ? long_cage_motion(rng, route, nominal_speed) : long_walk_motion(rng, route, nominal_speed);
      char name[64];
      std::snprintf(name, sizeof name, "long-%02d-%s-%s", ++long_index, route.scene, cage ? "cage" : "walk");
      BenchRun run{name, "long", nominal_speed, cage ? "rad/s" : "m/s",
                   scenario_node(route.scene, motion, rng.next_u64(), seed, ++index)};
      turn_on_error_sources(run.scenario, offset_s, cage);
      plan.push_back(std::move(run));
    }
  }
  // Issue 19's pairs: one cage run four times, the same in every byte but the
  // returns from the people (their randomness is their own).
  SensorRng people_rng(seed, "bench-people-runs");
  for (int k = 1; k <= kBenchPeopleCages; ++k) {
    const BenchRun base = cage_run(people_rng, k, ++index, seed);
    for (const char* variant : {"none", "walkers", "puller", "both"}) {
      char name[64];
      std::snprintf(name, sizeof name, "people-%02d-%s", k, variant);
      // A deep copy: assigning a YAML::Node would make the variants share one document.
      BenchRun run{name, "people", base.nominal_speed, base.speed_unit, YAML::Clone(base.scenario)};
      turn_on_error_sources(run.scenario, offset_s, true);
      const std::string v = variant;
      if (v == "walkers" || v == "both") run.scenario["people"]["walkers"]["count"] = kBenchWalkers;
      if (v == "puller" || v == "both") run.scenario["people"]["rope_puller"] = YAML::Node(YAML::NodeType::Map);
      plan.push_back(std::move(run));
    }
  }
  // The runaway runs (the hall): the long cage run down the
  // glass-ended hall, whose axis only a few pillars pin, with people walking
  // across, the rope puller ahead, mixed pixels and 1 ms of network jitter.
  SensorRng hall_rng(seed, "bench-hall-runs");
  for (int k = 0; k < kBenchHallRuns; ++k) {
    double nominal_speed = 0.0;
    YAML::Node motion = long_cage_motion(hall_rng, kHallRoute, nominal_speed);
    char name[64];
    std::snprintf(name, sizeof name, "long-%02d-hall-cage", ++long_index);
    BenchRun run{name, "long", nominal_speed, "rad/s", scenario_node(kHallRoute.scene, motion, hall_rng.next_u64(), seed, ++index)};
    turn_on_error_sources(run.scenario, offset_s, true);
    run.scenario["lidar"]["mixed_pixels"] = true;
    run.scenario["lidar"]["network_jitter_s"] = 0.001;
    run.scenario["people"]["walkers"]["count"] = kBenchWalkers;
    run.scenario["people"]["rope_puller"] = YAML::Node(YAML::NodeType::Map);
    plan.push_back(std::move(run));
  }
  return plan;
}

void write_bench(const std::vector<BenchRun>& plan, const fs::path& out, const BenchOptions& options,
                 std::ostream& progress) {
  const std::size_t count =
      options.max_runs > 0 ? std::min(plan.size(), static_cast<std::size_t>(options.max_runs)) : plan.size();
  fs::create_directories(out);
  std::vector<RunResult> results(count);
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  std::mutex progress_mutex;
  const auto t0 = std::chrono::steady_clock::now();

  auto worker = [&] {
    for (std::size_t i = next++; i < count; i = next++) {
      const BenchRun& run = plan[i];
      try {
        const fs::path dir = out / run.name;
        fs::create_directories(dir);
        std::ofstream(dir / "scenario.yaml") << YAML::Dump(run.scenario) << "\n";
        Scenario scenario = parse_scenario(run.scenario, run.name + "/scenario.yaml", dir);
        if (options.max_duration_s > 0.0)
          scenario.duration_s = std::min(scenario_duration_s(scenario), options.max_duration_s);
        results[i].duration_s = write_run(SimRun(scenario), dir).duration_s;
      } catch (const std::exception& e) {
        results[i].error = run.name + ": " + e.what();
      }
      const std::lock_guard lock(progress_mutex);
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      progress << "bench: [" << ++done << "/" << count << "] " << run.name << " ("
               << (results[i].error.empty() ? std::to_string(results[i].duration_s) + " s" : "FAILED") << ") "
               << static_cast<int>(elapsed) << " s elapsed" << std::endl;
    }
  };
  std::vector<std::thread> threads;
  for (int j = 1; j < options.jobs; ++j) threads.emplace_back(worker);
  worker();
  for (auto& t : threads) t.join();

  for (const auto& r : results) {
    if (!r.error.empty()) throw std::runtime_error(r.error);
  }
  write_index(std::vector<BenchRun>(plan.begin(), plan.begin() + static_cast<std::ptrdiff_t>(count)), results, out,
              options);
}

}  // namespace tumble::sim
