#include "tools/eval/scan_log.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "test/tools/eval/eval_test_support.hpp"

namespace tumble::eval {
namespace {

using test::TempDir;
using test::write_file;

const std::string kHeader =
    "scan_index,t_s,registered,converged,iterations,inlier_ratio,residual_m,degeneracy,points_in,points_used,"
    "sigma_s_median_m,deskew_ms,downsample_ms,normals_ms,weights_ms,matching_ms,solve_ms,map_ms,total_ms,latency_ms\n";

TEST(ScanLog, ReadsColumnsByNameAndFindsTheStages) {
  const TempDir dir("scanlog");
  write_file(dir.path() / "s.csv", kHeader +
                                       "0,1622032620.100000,1,1,7,0.9,0.01,0.2,28000,9000,0.001,0.5,1.0,2.0,0.3,4.0,"
                                       "0.2,1.1,9.1,12.5\n"
                                       "1,1622032620.200000,0,0,30,0.1,0.3,0.01,28000,9000,0.001,0.5,1.0,2.0,0.3,4.0,"
                                       "0.2,0.0,8.0,11.0\n");
  const ScanLog log = read_scan_log(dir.path() / "s.csv");
  EXPECT_EQ(log.scans(), 2u);
  EXPECT_EQ(log.column("registered"), (std::vector<double>{1.0, 0.0}));
  EXPECT_DOUBLE_EQ(log.column("latency_ms")[0], 12.5);
  EXPECT_EQ(log.stage_columns(), (std::vector<std::string>{"deskew_ms", "downsample_ms", "normals_ms", "weights_ms",
                                                           "matching_ms", "solve_ms", "map_ms"}));
  EXPECT_THROW(log.column("nope"), std::runtime_error);
}

TEST(ScanLog, AcceptsTrueAndFalse) {
  const TempDir dir("scanlog");
  write_file(dir.path() / "s.csv", "registered,total_ms\ntrue,3\nfalse,4\n");
  EXPECT_EQ(read_scan_log(dir.path() / "s.csv").column("registered"), (std::vector<double>{1.0, 0.0}));
}

TEST(ScanLog, NamesTheLineAndColumnOfABadRow) {
  const TempDir dir("scanlog");
  const auto path = dir.path() / "s.csv";
  const auto error_of = [&] {
    try {
      read_scan_log(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  write_file(path, "registered,total_ms\n1,3\n1\n");
  EXPECT_EQ(error_of(), path.string() + ":3: 1 fields, header has 2");
  write_file(path, "registered,total_ms\n1,3\n1,fast\n");
  EXPECT_EQ(error_of(), path.string() + ":3: total_ms 'fast' is not a number");
  write_file(path, "");
  EXPECT_EQ(error_of(), path.string() + ": empty (no header line)");
}

}  // namespace
}  // namespace tumble::eval
