// A bench with missing and corrupt runs: each is reported on one line naming
// the file, the good run is still evaluated and measured. The good run is a
// short simulated run at rest in a room (short and static: every simulated
// ray evaluates the motion, and ASan is slow).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>

#include "test/tools/calib/temp_dir.hpp"
#include "tools/calib/bench_calibration.hpp"
#include "tools/sim/run_writer.hpp"
#include "tools/sim/scenario.hpp"
#include "tools/sim/sim_run.hpp"

namespace tumble::calib {
namespace {

using test::TempDir;
using test::write_file;

void write_static_run(const std::filesystem::path& dir) {
  write_file(dir / "room.yaml",
             "objects:\n"
             "  - {type: box, center_m: [0.5, -0.3, 1.5], size_m: [9, 7, 3]}\n"
             "  - {type: box, center_m: [2.5, 1.0, 0.5], size_m: [1, 0.6, 1]}\n"
             "  - {type: cylinder, center_m: [-2, -2, 1], radius_m: 0.3, height_m: 2}\n");
  const sim::Scenario scenario =
      sim::parse_scenario(YAML::Load("scene: room.yaml\n"
                                     "motion: {type: static, duration_s: 0.45, origin: {xyz_m: [0, 0, 1]}}\n"
                                     "lidar: {dropout_probability: 0.5}\n"
                                     "seed: 5\n"),
                          "static.yaml", dir);
  sim::write_run(sim::SimRun(scenario), dir / "turn-good");
}

void copy_run(const std::filesystem::path& from, const std::filesystem::path& to) {
  std::filesystem::create_directories(to);
  for (const auto& entry : std::filesystem::directory_iterator(from))
    std::filesystem::copy_file(entry.path(), to / entry.path().filename());
}

void truncate_file(const std::filesystem::path& path, std::uintmax_t keep_bytes) {
  std::filesystem::resize_file(path, keep_bytes);
}

const RunOutcome& outcome(const BenchCalibration& bench, const std::string& name) {
  const auto it =
      std::find_if(bench.runs.begin(), bench.runs.end(), [&](const RunOutcome& r) { return r.name == name; });
  if (it == bench.runs.end()) throw std::runtime_error("no outcome for " + name);
  return *it;
}

TEST(BenchCalibration, ReportsBadRunsOneLineEachAndEvaluatesTheRest) {
  TempDir dir;
  const std::filesystem::path& bench = dir.path();
  write_static_run(bench);
  const std::filesystem::path good = bench / "turn-good";
  copy_run(good, bench / "turn-bad-truth");
  write_file(bench / "turn-bad-truth" / "ground_truth.tum",
             "# t x y z qx qy qz qw\n0 0 0 0 0 0 0 1\n0.001 0 0 0 zero\n");
  copy_run(good, bench / "turn-bad-lidar");
  write_file(bench / "turn-bad-lidar" / "lidar.pcap", "this is not a capture file, only some text");
  copy_run(good, bench / "turn-cut-imu");
  truncate_file(bench / "turn-cut-imu" / "imu.pcap", std::filesystem::file_size(good / "imu.pcap") / 2 + 3);
  copy_run(good, bench / "turn-no-imu");
  std::filesystem::remove(bench / "turn-no-imu" / "imu.pcap");
  copy_run(good, bench / "turn-no-manifest");
  std::filesystem::remove(bench / "turn-no-manifest" / "manifest.yaml");
  write_file(bench / "bench.csv",
             "name,kind,nominal_speed,speed_unit,duration_s,dir\n"
             "rail-gone,rail,1,m/s,10,rail-gone\n"
             "turn-bad-truth,turntable,2,rad/s,1,turn-bad-truth\n"
             "turn-good,turntable,2,rad/s,1,turn-good\n"
             "turn-bad-lidar,turntable,-2,rad/s,1,turn-bad-lidar\n"
             "turn-cut-imu,turntable,2,rad/s,1,turn-cut-imu\n"
             "turn-no-imu,turntable,2,rad/s,1,turn-no-imu\n"
             "turn-no-manifest,turntable,2,rad/s,1,turn-no-manifest\n"
             "cage-01,rolling_cage,5,rad/s,1,cage-01\n"
             "broken row\n");

  BenchOptions options;
  options.jobs = 2;
  options.params.odometry.fuser.static_duration_s = 0.2;  // the short run's rest
  options.params.residual.point_stride = 8;
  options.params.odometry.voxel_size_m = 0.25;  // a coarse registration: this test is about the inputs
  std::size_t progress_calls = 0;
  const BenchCalibration result =
      calibrate_bench(bench, options, [&](const RunOutcome&, std::size_t, std::size_t) { ++progress_calls; });

  EXPECT_EQ(progress_calls, 7u);
  EXPECT_EQ(result.other_runs, 1u);
  ASSERT_EQ(result.index.problems.size(), 1u);
  EXPECT_EQ(result.index.problems[0], "bench.csv:10: 1 fields, expected 6; row skipped");
  ASSERT_EQ(result.runs.size(), 7u);
  struct Expected {
    const char* run;
    const char* in_problem;
  };
  for (const Expected e :
       {Expected{"rail-gone", "rail-gone: missing run folder"},
        Expected{"turn-bad-truth", "ground_truth.tum:3: expected 8 numbers"},
        Expected{"turn-bad-lidar", "turn-bad-lidar/lidar.pcap"}, Expected{"turn-cut-imu", "turn-cut-imu/imu.pcap"},
        Expected{"turn-no-imu", "turn-no-imu/imu.pcap: missing"},
        Expected{"turn-no-manifest", "turn-no-manifest/manifest.yaml: missing"}}) {
    SCOPED_TRACE(e.run);
    const RunOutcome& r = outcome(result, e.run);
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.problem.find(e.in_problem), std::string::npos) << r.problem;
    EXPECT_EQ(r.problem.find('\n'), std::string::npos) << r.problem;
    EXPECT_TRUE(r.scans.empty());
  }

  const RunOutcome& ok = outcome(result, "turn-good");
  ASSERT_TRUE(ok.ok) << ok.problem;
  EXPECT_GT(ok.map_points, 1000u);
  ASSERT_GE(ok.scans.size(), 2u);
  for (const ScanRecord& s : ok.scans) {
    EXPECT_NEAR(s.duration_s, 0.1, 0.002);
    EXPECT_GT(s.residual_points, 1000u);
    EXPECT_GT(s.mean_range_m, 1.0);
    EXPECT_LT(s.mean_range_m, 6.0);
    EXPECT_LT(s.residual_m, 0.05);      // the 2 cm range noise against the averaged map
    EXPECT_LT(s.deskew_error_m, 0.01);  // at rest the odometry's de-skew is nearly the identity
    EXPECT_DOUBLE_EQ(s.speed, 0.0);
    EXPECT_TRUE(s.before_motion);
  }
  EXPECT_TRUE(result.calibration.has_angular);
  EXPECT_FALSE(result.calibration.has_linear);
}

}  // namespace
}  // namespace tumble::calib
