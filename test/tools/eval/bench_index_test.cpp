#include "tools/eval/bench_index.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "test/tools/eval/eval_test_support.hpp"

namespace tumble::eval {
namespace {

using test::TempDir;
using test::write_file;

const std::string kBenchCsv =
    "name,kind,nominal_speed,speed_unit,duration_s,dir\n"
    "rail-01-fwd-0.25mps,rail,0.25,m/s,11.6015,rail-01-fwd-0.25mps\n"
    "turntable-03-ccw-1.0rads,turntable,1,rad/s,9.5,turntable-03-ccw-1.0rads\n"
    "cage-01,rolling_cage,7.5,rad/s,10.2,cage-01\n"
    "cage-02,rolling_cage,5,rad/s,8.25,cage-02\n";

TEST(BenchIndex, ReadsEveryRun) {
  const TempDir dir("bench");
  write_file(dir.path() / "bench.csv", kBenchCsv);
  const std::vector<BenchRun> runs = read_bench_index(dir.path());
  ASSERT_EQ(runs.size(), 4u);
  EXPECT_EQ(runs[0].name, "rail-01-fwd-0.25mps");
  EXPECT_EQ(runs[0].kind, "rail");
  EXPECT_DOUBLE_EQ(runs[0].duration_s, 11.6015);
  EXPECT_EQ(runs[3].dir, dir.path() / "cage-02");
}

TEST(BenchIndex, FiltersByNamePatternAndKind) {
  const TempDir dir("bench");
  write_file(dir.path() / "bench.csv", kBenchCsv);
  const std::vector<BenchRun> runs = read_bench_index(dir.path());
  EXPECT_EQ(select_runs(runs, RunFilter{"*", {"rolling_cage"}}).size(), 2u);
  EXPECT_EQ(select_runs(runs, RunFilter{"*", {"cage"}}).size(), 2u);  // the paper's name for them
  EXPECT_EQ(select_runs(runs, RunFilter{"*", {"cage", "rail"}}).size(), 3u);
  EXPECT_TRUE(select_runs(runs, RunFilter{"*", {"rolling"}}).empty());
  EXPECT_EQ(kinds_of(runs), (std::vector<std::string>{"rail", "turntable", "rolling_cage"}));
  const auto one = select_runs(runs, RunFilter{"cage-0[2-9]", {}});
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].name, "cage-02");
  EXPECT_TRUE(select_runs(runs, RunFilter{"rail-*", {"cage"}}).empty());
  EXPECT_EQ(select_runs(runs, RunFilter{}).size(), 4u);
}

TEST(BenchIndex, ReportsAMissingOrBrokenIndex) {
  const TempDir dir("bench");
  EXPECT_THROW(read_bench_index(dir.path()), std::runtime_error);
  write_file(dir.path() / "bench.csv", "name,kind,duration_s,dir\ncage-01,cage,ten,cage-01\n");
  try {
    read_bench_index(dir.path());
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir.path() / "bench.csv").string() + ":2: duration_s 'ten' is not a positive number");
  }
  write_file(dir.path() / "bench.csv", "name,duration_s,dir\n");
  EXPECT_THROW(read_bench_index(dir.path()), std::runtime_error);
}

}  // namespace
}  // namespace tumble::eval
