#include "tools/eval/job_runner.hpp"

#include <cstdio>
#include <optional>

#include "tools/eval/child_processes.hpp"
#include "tools/eval/progress.hpp"

namespace tumble::eval {
namespace {

std::string progress_line(const RunResult& result) {
  std::string line = result.run + " " + result.variant.label() + ": " + to_string(result.status);
  if (result.status == RunStatus::Ok) {
    char figures[96];
    std::snprintf(figures, sizeof figures, " %.2f cm/m %.3f deg/m", result.drift->translation_cm_per_m,
                  result.drift->rotation_deg_per_m);
    line += figures;
  } else {
    line += " (" + result.message + ")";
  }
  return line;
}

// Stale outputs of an earlier evaluation must not be judged as this one's.
void remove_old_outputs(const JobPaths& paths) {
  std::error_code ignored;
  for (const auto& path : {paths.trajectory, paths.scan_log, paths.log}) std::filesystem::remove(path, ignored);
}

}  // namespace

std::vector<Job> plan_jobs(const std::vector<BenchRun>& runs, const std::vector<Variant>& variants) {
  std::vector<Job> jobs;
  for (const BenchRun& run : runs)
    for (const Variant& variant : variants) jobs.push_back(Job{run, variant});
  return jobs;
}

std::vector<RunResult> run_jobs(const std::vector<Job>& jobs, const RunnerOptions& options) {
  double total_weight = 0.0;
  for (const Job& job : jobs) total_weight += job.run.duration_s;
  Progress progress(jobs.size(), total_weight, options.progress);
  const auto report = [&](const Job& job, const RunResult& result) {
    if (options.progress != nullptr)
      progress.job_finished(job.run.duration_s, result.child.start_error.empty(), progress_line(result));
  };

  std::vector<std::optional<RunResult>> results(jobs.size());
  ChildPool pool;
  std::size_t next = 0;
  std::size_t finished = 0;
  while (finished < jobs.size()) {
    while (next < jobs.size() && pool.running() < std::max<std::size_t>(1, options.parallel_jobs)) {
      const Job& job = jobs[next];
      const JobPaths paths = job_paths(options.out_dir, job.run.name, job.variant);
      std::filesystem::create_directories(paths.trajectory.parent_path());
      remove_old_outputs(paths);
      if (const auto missing = run_input_problem(job.run)) {
        results[next] = failed_before_start(job.run, job.variant, *missing);
        report(job, *results[next]);
        ++finished;
      } else {
        pool.start(next, ChildCommand{tumbled_argv(options.tumbled, job.run, job.variant, paths), paths.log,
                                      options.timeout_s});
      }
      ++next;
    }
    if (finished == jobs.size()) break;
    for (auto& [index, outcome] : pool.wait(std::chrono::seconds(5))) {
      const Job& job = jobs[index];
      results[index] = evaluate_job(job.run, job.variant, job_paths(options.out_dir, job.run.name, job.variant),
                                    outcome, options.eval);
      report(job, *results[index]);
      ++finished;
    }
  }
  std::vector<RunResult> ordered;
  for (auto& result : results) ordered.push_back(std::move(*result));
  return ordered;
}

}  // namespace tumble::eval
