// The bench plan: the paper's kinds of runs, a static start on each,
// deterministic for a seed; and the folder layout it writes.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>

#include "test/tools/sim/sensor_test_support.hpp"
#include "tools/sim/bench.hpp"
#include "tools/sim/motion_load.hpp"
#include "tools/sim/run_writer.hpp"

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

}  // namespace
}  // namespace tumble::sim
