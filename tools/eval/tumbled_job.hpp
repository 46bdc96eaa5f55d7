// One evaluation job: a bench run replayed by the real tumbled binary with one
// weight model, de-skewing on or off (the agreement's replay command line),
// and where its outputs go under the evaluation folder.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tools/eval/bench_index.hpp"

namespace tumble::eval {

// The paper's models, in its figure's order.
inline const std::vector<std::string> kModels = {"NM", "TW", "VTW", "GVTW", "SAW"};

struct Variant {
  std::string model;  // one of kModels
  bool deskew = true;
  // "GVTW-deskew", "NM-no-deskew": file names and CSV cells.
  std::string label() const;
  bool operator==(const Variant&) const = default;
};

struct JobPaths {
  std::filesystem::path trajectory;  // OUT/trajectories/<run>/<label>.tum
  std::filesystem::path scan_log;    // OUT/trajectories/<run>/<label>.scans.csv
  std::filesystem::path log;         // OUT/trajectories/<run>/<label>.log (tumbled's stdout+stderr)
};

JobPaths job_paths(const std::filesystem::path& out_dir, const std::string& run_name, const Variant& variant);

struct TumbledSetup {
  std::filesystem::path tumbled;
  std::optional<std::filesystem::path> config;
};

std::vector<std::string> tumbled_argv(const TumbledSetup& setup, const BenchRun& run, const Variant& variant,
                                      const JobPaths& paths);

// What a run must hold before tumbled is worth starting: lidar.pcap and
// imu.pcap as readable regular files, and a ground_truth.tum that parses with
// at least 2 poses. Returns the first problem ("no lidar.pcap in DIR",
// "ground truth: FILE:LINE: ..."), or nothing.
std::optional<std::string> run_input_problem(const BenchRun& run);

// tumbled next to tumble-eval (an install), or in the build tree's daemon/
// folder (build/X/tools/eval/tumble-eval → build/X/daemon/tumbled). Throws
// std::runtime_error listing where it looked.
std::filesystem::path locate_tumbled(const std::filesystem::path& self_executable);

// Copies `tumbled` to DIR/.tumbled (replacing an earlier copy, even one that
// runs) and returns the copy: the evaluation runs the copy, so a rebuild that
// relinks the original cannot break its jobs ("Permission denied" on a
// half-written file). Throws std::runtime_error naming the file it could not copy.
std::filesystem::path copy_tumbled(const std::filesystem::path& tumbled, const std::filesystem::path& dir);

}  // namespace tumble::eval
