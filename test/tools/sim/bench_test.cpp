// The bench plan: the paper's kinds of runs, a static start on each,
// deterministic for a seed; and the folder layout it writes.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include "test/tools/sim/sensor_test_support.hpp"
#include "tools/sim/bench.hpp"
#include "tools/sim/motion_load.hpp"
#include "tools/sim/run_writer.hpp"
#include "tools/sim/scenario.hpp"

namespace tumble::sim {
namespace {

using test::TempDir;

std::string dump(const std::vector<BenchRun>& plan) {
  std::string s;
  for (const auto& r : plan) s += r.name + "\n" + YAML::Dump(r.scenario) + "\n";
  return s;
}

TEST(Bench, PlanHasRailTurntableAnd46CageRunsEachStartingStill) {
  const auto plan = plan_bench(7);
  std::map<std::string, int> kinds;
  bool rail_both_ways = false, table_both_ways = false;
  double fastest_rail = 0, fastest_table = 0;
  for (const auto& run : plan) {
    SCOPED_TRACE(run.name);
    ++kinds[run.kind];
    MotionLoadOptions options;
    options.source_name = run.name;
    options.key_path = "motion";
    const auto motion = load_motion(run.scenario["motion"], options);
    EXPECT_GE(motion->duration_s(), 5.0);
    EXPECT_LE(motion->duration_s(), 20.0);
    const MotionState start = motion->at(0.0);
    for (double t = 0.0; t <= kBenchStaticStartS; t += 0.25) {
      const MotionState s = motion->at(t);
      EXPECT_TRUE(s.T_wb.isApprox(start.T_wb, 1e-12));
      EXPECT_EQ(s.omega_b.norm() + s.v_w.norm(), 0.0);
    }
    // Inside the garage's clear lane the whole time, reaching the nominal speed.
    double top_speed = 0, top_rate = 0;
    for (double t = 0.0; t <= motion->duration_s(); t += 0.2) {
      const MotionState s = motion->at(t);
      EXPECT_LT(std::abs(s.T_wb.translation().x()), 14.0);
      EXPECT_LT(std::abs(s.T_wb.translation().y()), 3.0);
      top_speed = std::max(top_speed, s.v_w.norm());
      top_rate = std::max(top_rate, s.omega_b.norm());
    }
    if (run.kind == "rail") {
      EXPECT_NEAR(top_speed, std::abs(run.nominal_speed), 1e-6);
    } else {
      EXPECT_GE(top_rate, 0.999 * std::abs(run.nominal_speed));
    }
    if (run.kind == "rail") {
      rail_both_ways |= run.nominal_speed < 0;
      fastest_rail = std::max(fastest_rail, std::abs(run.nominal_speed));
    }
    if (run.kind == "turntable") {
      table_both_ways |= run.nominal_speed < 0;
      fastest_table = std::max(fastest_table, std::abs(run.nominal_speed));
    }
    EXPECT_EQ(run.scenario["lidar"]["unit_seed"].as<std::uint64_t>(), 7u);  // one lidar for the bench
  }
  EXPECT_EQ(kinds["rolling_cage"], kBenchCageRuns);
  EXPECT_GE(kinds["rail"], 10);
  EXPECT_GE(kinds["turntable"], 10);
  EXPECT_TRUE(rail_both_ways);
  EXPECT_TRUE(table_both_ways);
  EXPECT_EQ(fastest_rail, 3.5);   // the paper's top speeds
  EXPECT_EQ(fastest_table, 11.0);

  EXPECT_EQ(dump(plan), dump(plan_bench(7)));
  EXPECT_NE(dump(plan), dump(plan_bench(8)));
}

TEST(Bench, WritesRunFoldersAndAnIndex) {
  TempDir dir;
  BenchOptions options;
  options.seed = 7;
  options.jobs = 2;
  options.max_runs = 2;
  options.max_duration_s = 0.005;  // few rays: the garage is slow to cast under ASan
  std::ostringstream progress;
  write_bench(plan_bench(7), dir.path(), options, progress);
  const YAML::Node index = YAML::LoadFile((dir.path() / "bench.yaml").string());
  ASSERT_EQ(index["runs"].size(), 2u);
  EXPECT_EQ(index["seed"].as<std::uint64_t>(), 7u);
  for (const auto& run : index["runs"]) {
    const auto folder = dir.path() / run["dir"].as<std::string>();
    for (const char* f : {"scenario.yaml", kLidarPcapName, kImuPcapName, kGroundTruthName, kManifestName})
      EXPECT_TRUE(std::filesystem::exists(folder / f)) << folder / f;
    EXPECT_EQ(run["kind"].as<std::string>(), "rail");
    EXPECT_DOUBLE_EQ(run["duration_s"].as<double>(), 0.005);
  }
  std::ifstream csv(dir.path() / "bench.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "name,kind,nominal_speed,speed_unit,duration_s,dir");
  EXPECT_NE(progress.str().find("[2/2]"), std::string::npos);
}

std::unique_ptr<Motion> motion_of(const BenchRun& run) {
  MotionLoadOptions options;
  options.source_name = run.name;
  options.key_path = "motion";
  return load_motion(run.scenario["motion"], options);
}

TEST(RealisticBench, IsTodaysRunsWithEveryErrorSourceOnPlusLongRuns) {
  const auto today = plan_bench(7);
  const auto plan = plan_realistic_bench(7);
  ASSERT_EQ(plan.size(), today.size() + 3 * kBenchLongRunsPerScene + 4 * kBenchPeopleCages + kBenchHallRuns);
  const double offset_s = realistic_rig_imu_time_offset_s(7);
  EXPECT_GE(std::abs(offset_s), 0.002);
  EXPECT_LE(std::abs(offset_s), 0.005);
  for (std::size_t i = 0; i < plan.size(); ++i) {
    const BenchRun& run = plan[i];
    SCOPED_TRACE(run.name);
    if (i < today.size()) {
      EXPECT_EQ(run.name, today[i].name);
      EXPECT_EQ(YAML::Dump(run.scenario["motion"]), YAML::Dump(today[i].scenario["motion"]));
    }
    const Scenario s = parse_scenario(run.scenario, run.name, ".");
    EXPECT_TRUE(s.imu.scale_factor_error && s.imu.misalignment && s.imu.g_sensitivity && s.imu.temperature_drift &&
                s.imu.timestamp_jitter);
    EXPECT_TRUE(s.lidar.range_offset_error && s.lidar.intensity_range_bias && s.lidar.dark_surface_dropout);
    EXPECT_EQ(s.lidar.cage_bars.enabled, run.scenario["motion"]["type"].as<std::string>() == "rolling_cage");
    EXPECT_EQ(s.imu_time_offset_s, offset_s);
    EXPECT_EQ(*s.lidar_unit_seed, 7u);
  }
  EXPECT_EQ(dump(plan), dump(plan_realistic_bench(7)));
  EXPECT_NE(dump(plan), dump(plan_realistic_bench(8)));
}

TEST(RealisticBench, PeopleRunsComeInFoursThatDifferOnlyInTheirPeople) {
  const auto plan = plan_realistic_bench(5);
  std::vector<BenchRun> people;
  for (const BenchRun& run : plan)
    if (run.kind == "people") people.push_back(run);
  ASSERT_EQ(people.size(), 4u * kBenchPeopleCages);
  for (std::size_t k = 0; k < people.size(); k += 4) {
    SCOPED_TRACE(people[k].name);
    const std::string prefix = people[k].name.substr(0, 10);  // "people-01-"
    const char* variants[] = {"none", "walkers", "puller", "both"};
    std::vector<Scenario> s;
    for (std::size_t v = 0; v < 4; ++v) {
      EXPECT_EQ(people[k + v].name, prefix + variants[v]);
      s.push_back(parse_scenario(people[k + v].scenario, people[k + v].name, "."));
      YAML::Node without = YAML::Clone(people[k + v].scenario);
      without.remove("people");
      EXPECT_EQ(YAML::Dump(without), YAML::Dump(people[k].scenario));
    }
    EXPECT_EQ(people[k].scenario["motion"]["type"].as<std::string>(), "rolling_cage");
    EXPECT_FALSE(s[0].people.walkers || s[0].people.rope_puller);
    EXPECT_TRUE(s[1].people.walkers && !s[1].people.rope_puller);
    EXPECT_TRUE(!s[2].people.walkers && s[2].people.rope_puller);
    EXPECT_TRUE(s[3].people.walkers && s[3].people.rope_puller);
  }
  // Appended after the long runs of the garage, corridor and yard, which are unchanged.
  const auto first_people =
      std::find_if(plan.begin(), plan.end(), [](const BenchRun& run) { return run.kind == "people"; });
  ASSERT_NE(first_people, plan.begin());
  EXPECT_EQ((first_people - 1)->kind, "long");
  EXPECT_EQ(plan.back().name.find("-hall-cage"), plan.back().name.size() - 10);
}

TEST(RealisticBench, LongRunsGoOutAtLeast25mAndComeBackInAMinuteOrMore) {
  std::map<std::string, int> scenes;
  for (const BenchRun& run : plan_realistic_bench(3)) {
    if (run.kind != "long") continue;
    SCOPED_TRACE(run.name);
    ++scenes[run.scenario["scene"].as<std::string>()];
    const auto motion = motion_of(run);
    EXPECT_GE(motion->duration_s(), 60.0);
    const bool cage = run.scenario["motion"]["type"].as<std::string>() == "rolling_cage";
    EXPECT_EQ(run.speed_unit, cage ? "rad/s" : "m/s");
    EXPECT_GT(run.nominal_speed, 0.8);
    const Eigen::Vector3d start = motion->at(0.0).T_wb.translation();
    double path_m = 0.0, farthest_m = 0.0;
    Eigen::Vector3d previous = start;
    for (double t = 0.05; t <= motion->duration_s(); t += 0.05) {
      const Eigen::Vector3d p = motion->at(t).T_wb.translation();
      path_m += (p - previous).head<2>().norm();
      farthest_m = std::max(farthest_m, (p - start).head<2>().norm());
      previous = p;
      if (run.scenario["scene"].as<std::string>() != "yard") {
        EXPECT_LT(std::abs(p.y()), run.scenario["scene"].as<std::string>() == "garage" ? 4.0 : 1.0);
        EXPECT_LT(std::abs(p.x()), 25.0);
      }
    }
    EXPECT_GE(path_m, 50.0);
    EXPECT_GE(farthest_m, 25.0);
    EXPECT_LT((motion->at(motion->duration_s()).T_wb.translation() - start).head<2>().norm(), 0.5);
  }
  EXPECT_EQ(scenes["garage"], kBenchLongRunsPerScene);
  EXPECT_EQ(scenes["corridor"], kBenchLongRunsPerScene);
  EXPECT_EQ(scenes["yard"], kBenchLongRunsPerScene);
  EXPECT_EQ(scenes["hall"], kBenchHallRuns);
}

TEST(RealisticBench, HallRunsHaveThePeopleTheJitterAndTheMixedPixels) {
  int hall_runs = 0;
  for (const BenchRun& run : plan_realistic_bench(3)) {
    if (run.scenario["scene"].as<std::string>() != "hall") continue;
    SCOPED_TRACE(run.name);
    ++hall_runs;
    const Scenario s = parse_scenario(run.scenario, run.name, ".");
    EXPECT_TRUE(s.people.walkers && s.people.rope_puller);
    EXPECT_TRUE(s.lidar.mixed_pixels);
    EXPECT_EQ(s.lidar_link.network_jitter_s, 0.001);
    EXPECT_TRUE(s.lidar.cage_bars.enabled);
  }
  EXPECT_EQ(hall_runs, kBenchHallRuns);
}

TEST(RealisticBench, IndexSaysSoAndTodaysDoesNot) {
  for (const bool realistic : {false, true}) {
    TempDir dir;
    BenchOptions options;
    options.seed = 7;
    options.max_runs = 1;
    options.max_duration_s = 0.005;
    options.realistic = realistic;
    std::ostringstream progress;
    write_bench(realistic ? plan_realistic_bench(7) : plan_bench(7), dir.path(), options, progress);
    const YAML::Node index = YAML::LoadFile((dir.path() / "bench.yaml").string());
    EXPECT_EQ(static_cast<bool>(index["imu_time_offset_s"]), realistic);
    EXPECT_EQ(static_cast<bool>(index["error_sources"]), realistic);
    const YAML::Node manifest = YAML::LoadFile((dir.path() / index["runs"][0]["dir"].as<std::string>() / kManifestName).string());
    EXPECT_EQ(static_cast<bool>(manifest["imu"]["gyro_sensing_matrix"]), realistic);
    EXPECT_EQ(static_cast<bool>(manifest["lidar"]["range_offsets_m"]), realistic);
  }
}

}  // namespace
}  // namespace tumble::sim
