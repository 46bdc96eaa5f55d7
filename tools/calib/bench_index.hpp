// The bench's table of runs (tumble-sim bench: BENCH/bench.csv with the
// columns name,kind,nominal_speed,speed_unit,duration_s,dir). A bad row is
// reported and skipped, so one corrupt line costs one run, not the bench.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tumble::calib {

// The two calibration rigs of the paper (§IV, §V-A); the bench's other runs
// (the rolling cage) are for the evaluation, not for calibration.
enum class Rig { Rail, Turntable, Other };

struct BenchRun {
  std::string name;
  Rig rig = Rig::Other;
  std::string kind;          // as written in bench.csv
  double nominal_speed = 0;  // signed: m/s (rail) or rad/s (turntable)
  std::string speed_unit;
  double duration_s = 0;
  std::filesystem::path dir;  // absolute: BENCH/<dir>
};

struct BenchIndex {
  std::vector<BenchRun> runs;         // in bench.csv order
  std::vector<std::string> problems;  // one line per skipped row: "bench.csv:12: ..."
};

Rig rig_from_kind(const std::string& kind);

// Throws InputError when bench.csv is missing, unreadable or has another header.
BenchIndex read_bench_index(const std::filesystem::path& bench_dir);

}  // namespace tumble::calib
