// tumble-sim: the extreme-motion bench in software. `run` writes one
// scenario's recordings, `bench` a whole calibration + rolling-cage bench,
// `live` plays a scenario in real time to UDP and a pty.
#include <CLI/CLI.hpp>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "tools/sim/bench.hpp"
#include "tools/sim/live.hpp"
#include "tools/sim/run_writer.hpp"

namespace {

using namespace tumble::sim;

std::atomic<bool> g_stop{false};

void on_signal(int) { g_stop.store(true); }

void install_stop_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Scenario scenario_from(const std::string& path, const CLI::Option* seed_option, std::uint64_t seed) {
  Scenario s = load_scenario(path.empty() ? default_scenario_path() : std::filesystem::path(path));
  if (seed_option->count() > 0) s.seed = seed;
  return s;
}

int command_run(const Scenario& scenario, const std::string& out) {
  const auto t0 = std::chrono::steady_clock::now();
  const SimRun run(scenario);
  const RunSummary r = write_run(run, out);
  std::fprintf(stderr,
               "tumble-sim: wrote %s: %.2f s, %llu MSOP + %llu DIFOP packets, %llu IMU frames in %llu reads "
               "(%llu clipped), %llu ground-truth poses; took %.2f s\n",
               out.c_str(), r.duration_s, static_cast<unsigned long long>(r.msop_packets),
               static_cast<unsigned long long>(r.difop_packets), static_cast<unsigned long long>(r.imu_frames),
               static_cast<unsigned long long>(r.imu_reads), static_cast<unsigned long long>(r.imu_clipped_frames),
               static_cast<unsigned long long>(r.ground_truth_poses), seconds_since(t0));
  return 0;
}

int command_live(const Scenario& scenario, const LiveOptions& options) {
  install_stop_handlers();
  const LiveSummary s = run_live(scenario, options, std::cout, g_stop);
  std::fprintf(stderr,
               "tumble-sim live: %s: %llu MSOP + %llu DIFOP packets (%llu send failures), %llu IMU bytes in %llu "
               "writes (%llu dropped: pty full), %llu events late by > 1 ms (worst %.1f ms)\n",
               s.stopped ? "stopped" : "done", static_cast<unsigned long long>(s.msop_packets),
               static_cast<unsigned long long>(s.difop_packets), static_cast<unsigned long long>(s.udp_send_failures),
               static_cast<unsigned long long>(s.imu_bytes), static_cast<unsigned long long>(s.imu_reads),
               static_cast<unsigned long long>(s.imu_bytes_dropped), static_cast<unsigned long long>(s.late_events),
               s.max_late_s * 1e3);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tumble-sim: the extreme-motion sensor bench in software (RS-16 lidar + MTi-30 IMU)"};
  app.require_subcommand(1);

  std::string scenario_path, out_dir;
  std::uint64_t seed = 1;
  double duration_s = 0;

  CLI::App* run = app.add_subcommand("run", "write one run: lidar.pcap, imu.pcap, ground_truth.tum, manifest.yaml");
  run->add_option("SCENARIO", scenario_path, "scenario YAML (default: tools/sim/scenarios/default.yaml)");
  run->add_option("--out", out_dir, "output folder (created)")->required();
  CLI::Option* run_seed = run->add_option("--seed", seed, "override the scenario's seed");
  CLI::Option* run_duration =
      run->add_option("--duration", duration_s, "seconds to generate (at most the motion's length)")
          ->check(CLI::PositiveNumber);

  BenchOptions bench_options;
  CLI::App* bench = app.add_subcommand("bench", "write a whole bench: rail, turntable and 46 rolling-cage runs");
  bench->add_option("--seed", bench_options.seed, "bench seed (same seed, same bytes)")->required();
  bench->add_option("--out", out_dir, "output folder (created)")->required();
  bench->add_option("--jobs", bench_options.jobs, "runs generated in parallel")->check(CLI::Range(1, 64));
  bench->add_option("--runs", bench_options.max_runs, "write only the first N runs of the plan")
      ->check(CLI::PositiveNumber);
  bench->add_option("--max-duration", bench_options.max_duration_s, "cut every run to at most this many seconds")
      ->check(CLI::PositiveNumber);

  LiveOptions live_options;
  CLI::App* live = app.add_subcommand("live", "play a scenario in real time: UDP to the lidar ports, IMU into a pty");
  live->add_option("SCENARIO", scenario_path, "scenario YAML (default: tools/sim/scenarios/default.yaml)");
  live->add_option("--host", live_options.host, "lidar destination (loopback only unless --allow-remote)");
  live->add_option("--port-msop", live_options.msop_port, "MSOP destination port");
  live->add_option("--port-difop", live_options.difop_port, "DIFOP destination port");
  live->add_flag("--allow-remote", live_options.allow_remote, "allow a non-loopback --host");
  live->add_option("--rate", live_options.rate, "playback speed (1 = real time)")->check(CLI::PositiveNumber);
  CLI::Option* live_seed = live->add_option("--seed", seed, "override the scenario's seed");
  double live_duration_s = 0;
  CLI::Option* live_duration =
      live->add_option("--duration", live_duration_s, "stop after this many run seconds")->check(CLI::PositiveNumber);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    std::cerr << "tumble-sim: " << e.what() << " (see tumble-sim --help)\n";
    return 2;
  }

  try {
    if (run->parsed()) {
      Scenario scenario = scenario_from(scenario_path, run_seed, seed);
      if (run_duration->count() > 0) scenario.duration_s = duration_s;
      return command_run(scenario, out_dir);
    }
    if (bench->parsed()) {
      write_bench(plan_bench(bench_options.seed), out_dir, bench_options, std::cerr);
      return 0;
    }
    if (live->parsed()) {
      if (live_duration->count() > 0) live_options.duration_s = live_duration_s;
      return command_live(scenario_from(scenario_path, live_seed, seed), live_options);
    }
  } catch (const std::exception& e) {
    std::cerr << "tumble-sim: " << e.what() << "\n";
    return 2;
  }
  return 2;
}
