// The runs of a tumble-sim bench (BENCH_DIR/bench.csv) and the filters that
// pick a subset of them (--runs GLOB, --kinds).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tumble::eval {

struct BenchRun {
  std::string name;
  std::string kind;         // rail, turntable, rolling_cage
  double duration_s = 0.0;  // simulated duration (the replay's real-time length)
  std::filesystem::path dir;
};

// Reads bench.csv (header name,kind,nominal_speed,speed_unit,duration_s,dir; dir
// relative to the bench). Throws std::runtime_error "FILE[:LINE]: why".
std::vector<BenchRun> read_bench_index(const std::filesystem::path& bench_dir);

struct RunFilter {
  std::string name_glob = "*";  // shell pattern on the run name
  // Empty: every kind. "cage" stands for rolling_cage (the runs are named cage-NN).
  std::vector<std::string> kinds;
};

std::vector<BenchRun> select_runs(const std::vector<BenchRun>& runs, const RunFilter& filter);

// The distinct kinds, in order of first appearance (for "no run matches" messages).
std::vector<std::string> kinds_of(const std::vector<BenchRun>& runs);

}  // namespace tumble::eval
