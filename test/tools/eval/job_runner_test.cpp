// The runner's error handling: runs with missing inputs are reported one by
// one and cost no tumbled; an unstartable tumbled fails its jobs, not the
// evaluation. (No fake tumbled: real results come only from the real one.)
#include "tools/eval/job_runner.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <iterator>

#include "test/tools/eval/eval_test_support.hpp"

namespace tumble::eval {
namespace {

using test::TempDir;
using test::write_file;

TEST(JobRunner, PlansEveryVariantOfARunBeforeTheNextRun) {
  const std::vector<BenchRun> runs = {{"a", "cage", 1.0, "/a"}, {"b", "cage", 1.0, "/b"}};
  const std::vector<Job> jobs = plan_jobs(runs, {{"NM", false}, {"GVTW", true}});
  ASSERT_EQ(jobs.size(), 4u);
  EXPECT_EQ(jobs[1].run.name, "a");
  EXPECT_EQ(jobs[1].variant.label(), "GVTW-deskew");
  EXPECT_EQ(jobs[2].run.name, "b");
}

TEST(JobRunner, ReportsMissingRunsAndAnUnstartableTumbledRunByRun) {
  const TempDir dir("runner");
  const BenchRun missing_dir{"cage-01", "cage", 8.0, dir.path() / "cage-01"};
  const BenchRun missing_imu{"cage-02", "cage", 8.0, dir.path() / "cage-02"};
  write_file(missing_imu.dir / "lidar.pcap", "");
  write_file(missing_imu.dir / "ground_truth.tum", "");
  const BenchRun corrupt_truth{"cage-03", "cage", 8.0, dir.path() / "cage-03"};
  for (const char* name : {"lidar.pcap", "imu.pcap"}) write_file(corrupt_truth.dir / name, "");
  write_file(corrupt_truth.dir / "ground_truth.tum", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0\n");
  const BenchRun complete{"cage-04", "cage", 8.0, dir.path() / "cage-04"};
  for (const char* name : {"lidar.pcap", "imu.pcap"}) write_file(complete.dir / name, "");
  write_file(complete.dir / "ground_truth.tum", "1 0 0 0 0 0 0 1\n2 1 0 0 0 0 0 1\n");

  RunnerOptions options;
  options.tumbled.tumbled = dir.path() / "no-tumbled-here";
  options.out_dir = dir.path() / "eval";
  options.progress = nullptr;
  const std::vector<RunResult> results =
      run_jobs(plan_jobs({missing_dir, missing_imu, corrupt_truth, complete}, {{"NM", false}}), options);

  ASSERT_EQ(results.size(), 4u);
  EXPECT_EQ(results[0].run, "cage-01");
  EXPECT_EQ(results[0].status, RunStatus::Failed);
  EXPECT_EQ(results[0].message, "run folder " + missing_dir.dir.string() + " is missing");
  EXPECT_EQ(results[1].message, "no imu.pcap in " + missing_imu.dir.string());
  EXPECT_EQ(results[2].message, "ground truth: " + (corrupt_truth.dir / "ground_truth.tum").string() +
                                    ":2: expected 8 numbers (t x y z qx qy qz qw), got 7 fields");
  EXPECT_EQ(results[3].status, RunStatus::Failed);
  EXPECT_NE(results[3].message.find("tumbled: cannot start " + options.tumbled.tumbled.string()), std::string::npos)
      << results[3].message;
  EXPECT_TRUE(std::filesystem::is_directory(options.out_dir / "trajectories" / "cage-04"));
}

TEST(JobRunner, TumbledCommandLineFollowsTheAgreement) {
  const BenchRun run{"cage-05", "cage", 8.0, "/bench/cage-05"};
  const JobPaths paths = job_paths("/bench/eval", run.name, Variant{"VTW", false});
  EXPECT_EQ(paths.trajectory, "/bench/eval/trajectories/cage-05/VTW-no-deskew.tum");
  const std::vector<std::string> argv =
      tumbled_argv(TumbledSetup{"/build/daemon/tumbled", "/etc/t.yaml"}, run, Variant{"VTW", false}, paths);
  EXPECT_EQ(argv, (std::vector<std::string>{
                      "/build/daemon/tumbled", "--replay", "/bench/cage-05/lidar.pcap", "/bench/cage-05/imu.pcap",
                      "--rate", "max", "--lcm-url", "memq://", "--log-level", "warn", "--model", "VTW", "--no-deskew",
                      "--trajectory-out", "/bench/eval/trajectories/cage-05/VTW-no-deskew.tum", "--scan-log",
                      "/bench/eval/trajectories/cage-05/VTW-no-deskew.scans.csv", "--config", "/etc/t.yaml"}));
}

TEST(JobRunner, LocatesTumbledInTheBuildTreeOrSaysWhereItLooked) {
  const TempDir dir("runner");
  const auto self = dir.path() / "build" / "tools" / "eval" / "tumble-eval";
  try {
    locate_tumbled(self);
    FAIL() << "found a tumbled that is not there";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find((dir.path() / "build" / "daemon" / "tumbled").string()), std::string::npos);
  }
  const auto tumbled = dir.path() / "build" / "daemon" / "tumbled";
  write_file(tumbled, "");
  std::filesystem::permissions(tumbled, std::filesystem::perms::owner_all);
  EXPECT_EQ(locate_tumbled(self), tumbled);
}

TEST(JobRunner, RunsACopyOfTumbledThatARebuildLeavesAlone) {
  const TempDir dir("runner");
  const auto tumbled = dir.path() / "build" / "daemon" / "tumbled";
  write_file(tumbled, "first build");
  std::filesystem::permissions(tumbled, std::filesystem::perms::owner_all);
  const auto out = dir.path() / "eval";
  const auto copy = copy_tumbled(tumbled, out);
  EXPECT_EQ(copy, out / ".tumbled");
  EXPECT_EQ(test::read_file(copy), "first build");
  EXPECT_EQ(access(copy.c_str(), X_OK), 0);
  write_file(tumbled, "second build");
  EXPECT_EQ(test::read_file(copy), "first build");
  EXPECT_EQ(copy_tumbled(tumbled, out), copy);  // a later evaluation into the same folder
  EXPECT_EQ(test::read_file(copy), "second build");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(out), std::filesystem::directory_iterator()), 1);
  try {
    copy_tumbled(dir.path() / "no-tumbled-here", out);
    FAIL() << "copied a tumbled that is not there";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no-tumbled-here"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tumble::eval
