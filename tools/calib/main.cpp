// tumble-calib: fits the speed-uncertainty models of the paper (§V-A) on a
// bench of rail and turntable runs (tumble-sim bench output):
//   tumble-calib BENCH_DIR [--out DIR] [--jobs N] [--model NM|TW|VTW|GVTW|SAW] [--point-stride N]
//                [--noise-removal quadrature|subtract]
// For every rail/turntable run: a reference map from the ground truth, the
// odometry (fuser from imu.pcap + registration) over lidar.pcap, and per scan
// the residual of the odometry-de-skewed scan placed at its true pose; then
// per speed bin the quartiles, the noise at rest removed, the conversion
// r_v ≈ σ_v τ/2, r_ω ≈ σ_ω τ d/2, and the fit of the third quartile
// (log-normal β, κ, λ; cubic φ). See tools/calib/README.md for the
// choices and why.
// Writes DIR/calib.yaml (registration.lognormal_* and cubic_phi_rad_s for
// config/tumbled.yaml), DIR/residuals.csv, DIR/bins.csv, DIR/calib_linear.png,
// DIR/calib_angular.png (and their gnuplot scripts). A run whose files are
// missing or corrupt is reported on one line and left out.
// Exit: 0 calibrated (runs may have been left out), 1 nothing to calibrate
// from or an output could not be written, 2 bad command line or bench.csv.
// `tumble-calib rig RECORDING_DIR` is the lidar-IMU calibration of a rig
// (rig_command.hpp).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "core/point_weights.hpp"
#include "tools/calib/bench_calibration.hpp"
#include "tools/calib/input_error.hpp"
#include "tools/calib/plot.hpp"
#include "tools/calib/report.hpp"
#include "tools/calib/rig_command.hpp"
#include "tumble_build_info.hpp"

namespace {

using namespace tumble::calib;

void print_run_line(std::FILE* out, const RunOutcome& run) {
  if (!run.ok) {
    std::fprintf(out, "%s: skipped: %s\n", run.name.c_str(), run.problem.c_str());
    return;
  }
  std::fprintf(out,
               "%s: %zu scans measured (of %zu decoded; %zu before the fuser's initialisation or past the IMU, %zu "
               "outside the ground truth; %zu not registered), reference map %zu points\n",
               run.name.c_str(), run.scans.size(), run.scans_decoded, run.scans_without_trajectory,
               run.scans_without_truth, run.scans_not_registered, run.map_points);
}

int write_outputs(const BenchCalibration& bench, const std::filesystem::path& out_dir) {
  int status = 0;
  auto attempt = [&status](auto&& write) {
    try {
      write();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "tumble-calib: %s\n", e.what());
      status = 1;
    }
  };
  const Calibration& c = bench.calibration;
  attempt([&] { write_calib_yaml(out_dir / "calib.yaml", c); });
  attempt([&] {
    write_residuals_csv(out_dir / "residuals.csv", bench.runs, c, bench.rail_centres, bench.turntable_centres);
  });
  attempt([&] { write_bins_csv(out_dir / "bins.csv", c); });
  if (c.has_linear) attempt([&] { draw_plot(c.linear, out_dir / "calib_linear.png", out_dir / "calib_linear.gp"); });
  if (c.has_angular)
    attempt([&] { draw_plot(c.angular, out_dir / "calib_angular.png", out_dir / "calib_angular.gp"); });
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "rig") return tumble::calib::run_rig_command(argc - 1, argv + 1);
  CLI::App app{
      "tumble-calib: fit the speed-uncertainty models (paper section V-A) on a rail + turntable bench "
      "(tumble-calib rig --help: the lidar-IMU calibration of a rig)",
      "tumble-calib"};
  // Fires while parsing, so it needs none of the required arguments.
  app.set_version_flag("--version", std::string("tumble-calib ") + tumble::kVersion)->trigger_on_parse();
  std::string bench_dir, out_dir, model_name = "NM";
  unsigned jobs = 1;
  std::size_t point_stride = 1;
  std::string noise_removal = "quadrature";
  app.add_option("BENCH_DIR", bench_dir, "tumble-sim bench folder (bench.csv + one folder per run)")->required();
  app.add_option("--out", out_dir, "output folder (default BENCH_DIR/calib)");
  app.add_option("--jobs", jobs, "runs evaluated at once")->check(CLI::Range(1u, 64u));
  app.add_option("--model", model_name, "weight model of the odometry whose de-skew is measured (default NM)")
      ->check(CLI::IsMember({"NM", "TW", "VTW", "GVTW", "SAW"}));
  app.add_option("--point-stride", point_stride, "measure every n-th point of a scan (default 1: all)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000}));
  app.add_option("--noise-removal", noise_removal,
                 "how the noise at rest is taken out of a residual: quadrature (default) or subtract (the paper's)")
      ->check(CLI::IsMember({"quadrature", "subtract"}));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  // The drivers log recording problems as warnings; this tool reports them per run itself.
  spdlog::set_level(spdlog::level::err);

  BenchOptions options;
  options.jobs = jobs;
  options.params.odometry.weights.model = *tumble::weight_model_from_name(model_name);
  options.params.residual.point_stride = point_stride;
  options.axis.noise_removal = noise_removal == "subtract" ? NoiseRemoval::Subtract : NoiseRemoval::Quadrature;
  const std::filesystem::path out =
      out_dir.empty() ? std::filesystem::path(bench_dir) / "calib" : std::filesystem::path(out_dir);

  BenchCalibration bench;
  try {
    bench = calibrate_bench(bench_dir, options, [](const RunOutcome& run, std::size_t done, std::size_t total) {
      std::fprintf(stderr, "[%zu/%zu] ", done, total);
      print_run_line(stderr, run);
    });
  } catch (const InputError& e) {
    std::fprintf(stderr, "tumble-calib: %s\n", e.what());
    return 2;
  }

  for (const std::string& problem : bench.index.problems) std::printf("%s\n", problem.c_str());
  for (const RunOutcome& run : bench.runs) print_run_line(stdout, run);
  if (bench.other_runs > 0)
    std::printf("runs of other kinds (rolling cage), not used for calibration: %zu\n", bench.other_runs);
  const Calibration& c = bench.calibration;
  if (!c.has_linear && !c.has_angular) {
    std::fprintf(stderr, "tumble-calib: no usable rail or turntable run in %s\n", bench_dir.c_str());
    return 1;
  }
  std::printf("\n");
  print_summary(stdout, c);
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) {
    std::fprintf(stderr, "tumble-calib: cannot create %s: %s\n", out.string().c_str(), ec.message().c_str());
    return 1;
  }
  const int status = write_outputs(bench, out);
  std::printf("\nwrote %s/{calib.yaml, residuals.csv, bins.csv, calib_linear.png, calib_angular.png}\n",
              out.string().c_str());
  return status;
}
