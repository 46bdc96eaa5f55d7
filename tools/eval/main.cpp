// tumble-eval: runs tumbled over a tumble-sim bench and reports the paper's
// figures (matrix) or what the pipeline costs (speed); scores one finished
// tumbled run against its ground truth (score). See README.md.
// Exit codes: 0 every job evaluated, 1 some job failed or the plot could not
// be drawn (all else is still reported), 2 usage error or unreadable bench.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "tools/eval/bench_index.hpp"
#include "tools/eval/box_plot.hpp"
#include "tools/eval/drift.hpp"
#include "tools/eval/imu_attitude.hpp"
#include "tools/eval/integrity_report.hpp"
#include "tools/eval/job_runner.hpp"
#include "tools/eval/matrix_report.hpp"
#include "tools/eval/run_plots.hpp"
#include "tools/eval/run_score.hpp"
#include "tools/eval/runaway.hpp"
#include "tools/eval/scan_log.hpp"
#include "tools/eval/speed_report.hpp"
#include "tools/eval/tum_file.hpp"
#include "tools/eval/tumbled_job.hpp"
#include "tumble_build_info.hpp"

namespace {

using namespace tumble::eval;

constexpr int kExitSomeFailed = 1;
constexpr int kExitUsage = 2;

// --runs and --kinds, as every subcommand over a bench takes them.
void add_selection_options(CLI::App& command, RunFilter& selection) {
  command.add_option("--runs", selection.name_glob, "only runs whose name matches this shell pattern")
      ->capture_default_str();
  command
      .add_option("--kinds", selection.kinds,
                  "only these kinds of run, as bench.csv names them (rail, turntable, rolling_cage, long, "
                  "people; cage = rolling_cage)")
      ->delimiter(',');
}

std::string join(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : ",") + item;
  return text;
}

std::string selection_text(const RunFilter& selection) {
  return "runs '" + selection.name_glob + "', kinds " + (selection.kinds.empty() ? "all" : join(selection.kinds));
}

// The runs of bench_dir that `selection` picks; none is an error that lists the bench's kinds.
std::vector<BenchRun> selected_runs(const std::string& bench_dir, const RunFilter& selection) {
  const std::vector<BenchRun> all = read_bench_index(bench_dir);
  std::vector<BenchRun> runs = select_runs(all, selection);
  if (runs.empty())
    throw std::runtime_error("no run of " + bench_dir + " matches " + selection_text(selection) +
                             " (its kinds: " + join(kinds_of(all)) + ")");
  return runs;
}

struct CommonOptions {
  std::string bench_dir;
  std::string out_dir;
  std::size_t jobs = 2;
  std::string tumbled;
  std::string config;
  RunFilter selection;
  std::vector<std::string> models;
  std::string deskew = "both";
  double timeout_s = 600.0;
};

void add_common_options(CLI::App& command, CommonOptions& options) {
  command.add_option("bench_dir", options.bench_dir, "tumble-sim bench folder (with bench.csv)")->required();
  command.add_option("--out", options.out_dir, "output folder (default BENCH_DIR/eval)");
  command.add_option("--jobs", options.jobs, "tumbled processes at a time")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command.add_option("--tumbled", options.tumbled,
                     "tumbled binary (default: next to tumble-eval or in the build tree)");
  command.add_option("--config", options.config, "tumbled --config FILE for every job");
  add_selection_options(command, options.selection);
  command.add_option("--models", options.models, "weight models (NM,TW,VTW,GVTW,SAW)")
      ->delimiter(',')
      ->check(CLI::IsMember(kModels))
      ->capture_default_str();
  command.add_option("--deskew", options.deskew, "de-skew on, off or both")
      ->check(CLI::IsMember({"on", "off", "both"}))
      ->capture_default_str();
  command.add_option("--timeout-s", options.timeout_s, "kill a tumbled that runs longer than this")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
}

std::vector<Variant> variants_of(const CommonOptions& options) {
  std::vector<Variant> variants;
  for (const bool deskew : {false, true}) {
    if (options.deskew == (deskew ? "off" : "on")) continue;
    for (const std::string& model : kModels)
      if (std::find(options.models.begin(), options.models.end(), model) != options.models.end())
        variants.push_back(Variant{model, deskew});
  }
  return variants;
}

std::string selection_text(const CommonOptions& options) {
  return selection_text(options.selection) + ", models " + join(options.models) + ", de-skew " + options.deskew;
}

RunnerOptions runner_options(const CommonOptions& options, const char* argv0) {
  RunnerOptions runner;
  std::error_code error;
  std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) self = argv0;
  runner.out_dir = options.out_dir.empty() ? std::filesystem::path(options.bench_dir) / "eval"
                                           : std::filesystem::path(options.out_dir);
  // The jobs run a copy, so a rebuild during the evaluation cannot break them.
  runner.tumbled.tumbled = copy_tumbled(
      options.tumbled.empty() ? locate_tumbled(self) : std::filesystem::path(options.tumbled), runner.out_dir);
  if (!options.config.empty()) runner.tumbled.config = std::filesystem::absolute(options.config);
  runner.parallel_jobs = options.jobs;
  runner.timeout_s = options.timeout_s;
  return runner;
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

int run_matrix(const CommonOptions& options, const EvalOptions& eval, const char* argv0) {
  const std::vector<BenchRun> runs = selected_runs(options.bench_dir, options.selection);
  RunnerOptions runner = runner_options(options, argv0);
  runner.eval = eval;
  std::filesystem::create_directories(runner.out_dir);
  const std::vector<Variant> variants = variants_of(options);
  std::fprintf(stderr, "eval: %zu runs × %zu variants, %zu at a time, tumbled %s → %s\n", runs.size(), variants.size(),
               runner.parallel_jobs, runner.tumbled.tumbled.c_str(), runner.out_dir.c_str());
  const std::vector<RunResult> results = run_jobs(plan_jobs(runs, variants), runner);

  const std::vector<CellSummary> cells = summarize_cells(results, variants);
  write_runs_csv(runner.out_dir / "runs.csv", results);
  const std::string plot_problem = draw_box_plot(cells, runner.out_dir / "boxplot.gp", runner.out_dir / "boxplot.png");
  if (!plot_problem.empty()) std::fprintf(stderr, "eval: no box plot: %s\n", plot_problem.c_str());
  MatrixDescription description{options.bench_dir, selection_text(options), runs.size(), eval,
                                plot_problem.empty() ? "boxplot.png" : ""};
  const std::string markdown = results_markdown(description, cells, results);
  write_text(runner.out_dir / "results.md", markdown);
  std::fputs(markdown.c_str(), stdout);

  std::size_t failed = 0;
  for (const RunResult& result : results) failed += result.status == RunStatus::Failed ? 1 : 0;
  std::fprintf(stderr, "eval: wrote %s (results.md, runs.csv, boxplot.png, trajectories/); %zu of %zu jobs failed\n",
               runner.out_dir.c_str(), failed, results.size());
  return failed > 0 || !plot_problem.empty() ? kExitSomeFailed : 0;
}

int run_speed(const CommonOptions& options, const char* argv0) {
  const std::vector<BenchRun> runs = selected_runs(options.bench_dir, options.selection);
  const RunnerOptions runner = runner_options(options, argv0);
  std::filesystem::create_directories(runner.out_dir);
  const std::vector<Job> jobs = plan_jobs(runs, variants_of(options));
  std::fprintf(stderr, "eval: speed over %zu jobs, %zu at a time, tumbled %s\n", jobs.size(), runner.parallel_jobs,
               runner.tumbled.tumbled.c_str());
  const std::vector<RunResult> results = run_jobs(jobs, runner);
  std::vector<std::filesystem::path> scan_logs;
  for (const Job& job : jobs) scan_logs.push_back(job_paths(runner.out_dir, job.run.name, job.variant).scan_log);
  const SpeedSummary summary = summarize_speed(results, scan_logs);
  const std::string markdown =
      speed_markdown(summary, "Bench `" + options.bench_dir + "`, " + selection_text(options) + ", " +
                                  std::to_string(runner.parallel_jobs) + " tumbled at a time.");
  write_text(runner.out_dir / "speed.md", markdown);
  std::fputs(markdown.c_str(), stdout);
  return summary.failed_runs > 0 ? kExitSomeFailed : 0;
}

struct ScoreOptions {
  std::string ground_truth;
  std::string trajectory;
  std::string scan_log;
  std::string plots_dir;
  DriftOptions drift;
};

int run_score(const ScoreOptions& options) {
  const std::optional<std::filesystem::path> scan_log =
      options.scan_log.empty() ? std::nullopt : std::optional<std::filesystem::path>(options.scan_log);
  const RunScore score = score_run(options.ground_truth, options.trajectory, scan_log, options.drift);
  std::fputs(score_markdown(score).c_str(), stdout);
  if (options.plots_dir.empty()) return 0;
  const std::string error =
      draw_run_plots(read_tum(options.ground_truth), read_tum(options.trajectory), options.plots_dir);
  if (!error.empty()) {
    std::fprintf(stderr, "tumble-eval score --plots: %s\n", error.c_str());
    return 1;
  }
  std::printf("\nPlots: %s/trajectory_top.png, trajectory_side.png, error.png\n", options.plots_dir.c_str());
  return 0;
}

struct ImuOptions {
  std::string recording;
  std::string out_dir = "imu-eval";
  ImuEvalOptions eval;
};

int run_imu(const ImuOptions& options) {
  const ImuEvaluation evaluation = evaluate_imu_recording(options.recording, options.eval);
  const std::filesystem::path out(options.out_dir);
  std::filesystem::create_directories(out);
  write_attitude_tum(evaluation, out / "attitude.tum");
  const std::string markdown = imu_report_markdown(evaluation);
  write_text(out / "report.md", markdown);
  std::fputs(markdown.c_str(), stdout);
  if (evaluation.attitude.empty()) return 0;
  const std::string plot = draw_roll_pitch(evaluation, out / "roll_pitch.gp", out / "roll_pitch.png");
  if (plot.empty()) return 0;
  std::fprintf(stderr, "tumble-eval imu: no plot: %s\n", plot.c_str());
  return kExitSomeFailed;
}

struct IntegrityOptions {
  std::string bench_dir;
  std::string eval_dir;
  RunFilter selection;
  std::string model = "GVTW";
  std::string deskew = "on";
  std::vector<double> thresholds_m{0.03, 0.035, 0.04, 0.045, 0.05};
  std::size_t window = 10;
};

// A run of kind `long` ends where it started: its final error says little, its RPE over 10 m does.
constexpr double kLongRunSegment_m = 10.0;

int run_integrity(const IntegrityOptions& options) {
  const std::vector<BenchRun> runs = selected_runs(options.bench_dir, options.selection);
  const Variant variant{options.model, options.deskew == "on"};
  std::vector<RunIntegrity> scored;
  for (const BenchRun& run : runs) {
    const JobPaths paths = job_paths(options.eval_dir, run.name, variant);
    RunIntegrity result;
    result.name = run.name;
    if (!std::filesystem::exists(paths.trajectory) || !std::filesystem::exists(paths.scan_log)) {
      std::fprintf(stderr, "tumble-eval integrity: %s: no %s trajectory or scan log in %s: counted as diverged\n",
                   run.name.c_str(), variant.label().c_str(), options.eval_dir.c_str());
      result.error_cm_per_m = std::numeric_limits<double>::infinity();
      scored.push_back(result);
      continue;
    }
    const PoseSeries truth = read_tum(run.dir / "ground_truth.tum");
    const PoseSeries estimate = read_tum(paths.trajectory);
    const bool long_run = run.kind == "long";
    const DriftResult drift = evaluate_drift(truth, estimate, DriftOptions{long_run ? kLongRunSegment_m : 1.0});
    result.error_cm_per_m = long_run ? drift.rpe_translation_cm_per_m : drift.translation_cm_per_m;
    result.distance_m = drift.distance_m;
    const ScanLog log = read_scan_log(paths.scan_log);
    result.scans = score_scans(truth, estimate, log, options.window);
    result.runaway = runaway_of(truth, estimate, log);
    scored.push_back(std::move(result));
  }
  std::fputs(integrity_markdown(scored, options.thresholds_m).c_str(), stdout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tumble-eval: the paper's evaluation of tumbled on a tumble-sim bench", "tumble-eval"};
  // Fires while parsing, so it needs none of the required arguments.
  app.set_version_flag("--version", std::string("tumble-eval ") + tumble::kVersion)->trigger_on_parse();
  app.set_help_all_flag("--help-all", "Print the help of every subcommand and exit");
  app.require_subcommand(1);

  CommonOptions matrix_options;
  matrix_options.models = kModels;
  EvalOptions eval;
  CLI::App* matrix = app.add_subcommand(
      "matrix", "every run × {NM,TW,VTW,GVTW,SAW} × {no de-skew, de-skew}: results.md, runs.csv, boxplot.png");
  add_common_options(*matrix, matrix_options);
  matrix->add_option("--segment-m", eval.drift.segment_m, "RPE segment length (travelled distance)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  matrix->add_option("--diverged-cm-per-m", eval.limits.translation_cm_per_m, "diverged above this translation error")
      ->capture_default_str();
  matrix->add_option("--diverged-deg-per-m", eval.limits.rotation_deg_per_m, "diverged above this rotation error")
      ->capture_default_str();
  matrix
      ->add_option("--max-end-gap-s", eval.limits.max_end_gap_s,
                   "diverged when the last pose is this long before the run ends")
      ->capture_default_str();

  CommonOptions speed_options;
  speed_options.jobs = 1;  // timing: one tumbled at a time unless asked
  speed_options.models = {"GVTW"};
  speed_options.deskew = "on";
  CLI::App* speed = app.add_subcommand("speed", "per-stage time per scan, p50/p99, multiple of real time, peak RSS");
  add_common_options(*speed, speed_options);

  ScoreOptions score_options;
  CLI::App* score =
      app.add_subcommand("score", "one tumbled trajectory against ground truth; from its scan log, the stage "
                                  "times and how far its pose ran away while published as good");
  score->add_option("ground_truth", score_options.ground_truth, "ground truth (TUM), e.g. RUN/ground_truth.tum")
      ->required()
      ->check(CLI::ExistingFile);
  score->add_option("trajectory", score_options.trajectory, "tumbled --trajectory-out file (TUM)")
      ->required()
      ->check(CLI::ExistingFile);
  score->add_option("--scan-log", score_options.scan_log, "tumbled --scan-log file (CSV)")->check(CLI::ExistingFile);
  score->add_option("--plots", score_options.plots_dir,
                    "also draw the trajectory against ground truth (top, side) and the error over time as PNGs "
                    "in this folder (gnuplot)");
  score->add_option("--segment-m", score_options.drift.segment_m, "RPE segment length (travelled distance)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);

  ImuOptions imu_options;
  CLI::App* imu = app.add_subcommand(
      "imu", "the fuser alone on an IMU recording: attitude.tum, report.md (tilt against the still accelerometer "
             "and the device), roll_pitch.png");
  imu->add_option("RECORDING", imu_options.recording, "imu.pcap (tumbled --record, tumble-sim) or a raw MTi byte stream")
      ->required()
      ->check(CLI::ExistingFile);
  imu->add_option("--out", imu_options.out_dir, "output folder (created)")->capture_default_str();
  imu->add_option("--fuser-static-s", imu_options.eval.fuser_static_s, "the fuser's initial still window")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  imu->add_option("--still-min-s", imu_options.eval.still_min_s, "shortest still period reported")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);

  IntegrityOptions integrity_options;
  CLI::App* integrity = app.add_subcommand(
      "integrity", "tumbled's expected error (scan log) as a detector of wrong poses, the NEES of its published "
                   "covariance, and how far a pose ran away while published as good, against ground truth, on a "
                   "finished matrix");
  integrity->add_option("bench_dir", integrity_options.bench_dir, "tumble-sim bench folder (with bench.csv)")
      ->required()
      ->check(CLI::ExistingDirectory);
  integrity->add_option("eval_dir", integrity_options.eval_dir, "a tumble-eval matrix --out folder over that bench")
      ->required()
      ->check(CLI::ExistingDirectory);
  add_selection_options(*integrity, integrity_options.selection);
  integrity->add_option("--model", integrity_options.model, "the weight model's runs to score")
      ->check(CLI::IsMember(kModels))
      ->capture_default_str();
  integrity->add_option("--deskew", integrity_options.deskew, "the de-skew setting's runs to score")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  integrity->add_option("--threshold-m", integrity_options.thresholds_m, "expected-error thresholds, one row each")
      ->delimiter(',')
      ->capture_default_str();
  integrity->add_option("--window", integrity_options.window, "scans over which a slip is judged")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitUsage;
  }
  try {
    if (matrix->parsed()) return run_matrix(matrix_options, eval, argv[0]);
    if (score->parsed()) return run_score(score_options);
    if (imu->parsed()) return run_imu(imu_options);
    if (integrity->parsed()) return run_integrity(integrity_options);
    return run_speed(speed_options, argv[0]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tumble-eval: %s\n", e.what());
    return kExitUsage;
  }
}
