// bench.csv: good rows become runs, each bad row is one problem line, and a
// file that is not a bench table stops everything.
#include "tools/calib/bench_index.hpp"

#include <gtest/gtest.h>

#include "test/tools/calib/temp_dir.hpp"
#include "tools/calib/input_error.hpp"

namespace tumble::calib {
namespace {

using test::TempDir;
using test::write_file;

TEST(BenchIndex, ReadsRunsAndReportsEachBadRow) {
  TempDir dir;
  write_file(dir.path() / "bench.csv",
             "name,kind,nominal_speed,speed_unit,duration_s,dir\r\n"
             "rail-01,rail,-0.25,m/s,11.6,rail-01\n"
             "turn-02,turntable,4,rad/s,6.6,turn-02\n"
             "cage-03,rolling_cage,-3.7,rad/s,8.9,cage-03\n"
             "\n"
             "rail-04,rail,fast,m/s,11,rail-04\n"
             "rail-05,rail,1,m/s,0,rail-05\n"
             "rail-06,rail,1,m/s,10\n"
             "turn-07,turntable,1,m/s,10,turn-07\n"
             ",rail,1,m/s,10,x\n");
  const BenchIndex index = read_bench_index(dir.path());
  ASSERT_EQ(index.runs.size(), 3u);
  EXPECT_EQ(index.runs[0].name, "rail-01");
  EXPECT_EQ(index.runs[0].rig, Rig::Rail);
  EXPECT_DOUBLE_EQ(index.runs[0].nominal_speed, -0.25);
  EXPECT_EQ(index.runs[0].dir, dir.path() / "rail-01");
  EXPECT_EQ(index.runs[1].rig, Rig::Turntable);
  EXPECT_EQ(index.runs[2].rig, Rig::Other);
  ASSERT_EQ(index.problems.size(), 5u);
  EXPECT_EQ(index.problems[0], "bench.csv:6: nominal_speed \"fast\" is not a number; row skipped");
  EXPECT_EQ(index.problems[1], "bench.csv:7: duration_s \"0\" is not a positive number; row skipped");
  EXPECT_EQ(index.problems[2], "bench.csv:8: 5 fields, expected 6; row skipped");
  EXPECT_EQ(index.problems[3], "bench.csv:9: turntable run with speed_unit \"m/s\", expected rad/s; row skipped");
  EXPECT_EQ(index.problems[4], "bench.csv:10: empty name or dir; row skipped");
}

TEST(BenchIndex, AMissingOrForeignTableThrowsNamingTheFile) {
  TempDir dir;
  try {
    read_bench_index(dir.path());
    FAIL() << "no bench.csv";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bench.csv: cannot be opened"), std::string::npos) << e.what();
  }
  write_file(dir.path() / "bench.csv", "run,speed\nrail-01,1\n");
  try {
    read_bench_index(dir.path());
    FAIL() << "wrong header";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bench.csv:1: header is not"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tumble::calib
