#include "tools/calib/bench_calibration.hpp"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>

namespace tumble::calib {

BenchCalibration calibrate_bench(const std::filesystem::path& bench_dir, const BenchOptions& options,
                                 const RunProgress& progress) {
  BenchCalibration out;
  out.index = read_bench_index(bench_dir);
  std::vector<const BenchRun*> todo;
  std::vector<double> rail_speeds, turntable_speeds;
  for (const BenchRun& run : out.index.runs) {
    if (run.rig == Rig::Other) {
      ++out.other_runs;
      continue;
    }
    todo.push_back(&run);
    (run.rig == Rig::Rail ? rail_speeds : turntable_speeds).push_back(run.nominal_speed);
  }
  out.rail_centres = bin_centres(rail_speeds);
  out.turntable_centres = bin_centres(turntable_speeds);

  out.runs.resize(todo.size());
  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  std::mutex progress_mutex;
  auto worker = [&] {
    for (std::size_t i = next++; i < todo.size(); i = next++) {
      out.runs[i] = evaluate_run(*todo[i], options.params);
      const std::lock_guard<std::mutex> lock(progress_mutex);
      ++done;
      if (progress) progress(out.runs[i], done, todo.size());
    }
  };
  const unsigned jobs =
      std::clamp<unsigned>(options.jobs, 1, static_cast<unsigned>(std::max<std::size_t>(todo.size(), 1)));
  std::vector<std::thread> threads;
  for (unsigned j = 1; j < jobs; ++j) threads.emplace_back(worker);
  worker();
  for (std::thread& t : threads) t.join();

  std::vector<ScanRecord> rail, turntable;
  for (const RunOutcome& run : out.runs) {
    if (!run.ok) continue;
    std::vector<ScanRecord>& into = run.rig == Rig::Rail ? rail : turntable;
    into.insert(into.end(), run.scans.begin(), run.scans.end());
  }
  Calibration& c = out.calibration;
  c.bench = bench_dir.string();
  c.has_linear = !rail.empty();
  c.has_angular = !turntable.empty();
  if (c.has_linear) c.linear = calibrate_axis(Rig::Rail, rail, out.rail_centres, options.axis);
  if (c.has_angular) c.angular = calibrate_axis(Rig::Turntable, turntable, out.turntable_centres, options.axis);
  return out;
}

}  // namespace tumble::calib
