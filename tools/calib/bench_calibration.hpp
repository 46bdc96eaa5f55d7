// The whole bench: every rail and turntable run evaluated (in parallel when
// asked), runs that cannot be used reported one line each and left out, then
// one AxisCalibration per rig from the scans of the usable runs.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <vector>

#include "tools/calib/bench_index.hpp"
#include "tools/calib/report.hpp"
#include "tools/calib/run_evaluation.hpp"

namespace tumble::calib {

struct BenchOptions {
  CalibParams params;
  AxisOptions axis;
  unsigned jobs = 1;
};

struct BenchCalibration {
  BenchIndex index;
  std::vector<RunOutcome> runs;  // the rail and turntable runs, in bench.csv order
  std::size_t other_runs = 0;    // runs of other kinds (rolling cage), not used
  std::vector<double> rail_centres;
  std::vector<double> turntable_centres;
  Calibration calibration;
};

// Called from the worker threads, one at a time, as each run finishes.
using RunProgress = std::function<void(const RunOutcome& run, std::size_t done, std::size_t total)>;

// Throws InputError when bench.csv itself is unusable.
BenchCalibration calibrate_bench(const std::filesystem::path& bench_dir, const BenchOptions& options,
                                 const RunProgress& progress = {});

}  // namespace tumble::calib
