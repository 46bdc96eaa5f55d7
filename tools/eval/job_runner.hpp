// Runs jobs (bench run × variant) through tumbled, N at a time, and judges
// each as it ends. Inputs are checked before tumbled starts, so a missing or
// corrupt run costs nothing and the others go on.
#pragma once

#include <cstdio>
#include <filesystem>
#include <vector>

#include "tools/eval/bench_index.hpp"
#include "tools/eval/run_result.hpp"
#include "tools/eval/tumbled_job.hpp"

namespace tumble::eval {

struct Job {
  BenchRun run;
  Variant variant;
};

// Run-major: every variant of a run, then the next run.
std::vector<Job> plan_jobs(const std::vector<BenchRun>& runs, const std::vector<Variant>& variants);

struct RunnerOptions {
  TumbledSetup tumbled;
  std::filesystem::path out_dir;
  std::size_t parallel_jobs = 2;
  double timeout_s = 600.0;  // per tumbled
  EvalOptions eval;
  std::FILE* progress = stderr;  // nullptr: quiet
};

// Results in the order of `jobs`. Throws only when the output folder cannot be made.
std::vector<RunResult> run_jobs(const std::vector<Job>& jobs, const RunnerOptions& options);

}  // namespace tumble::eval
