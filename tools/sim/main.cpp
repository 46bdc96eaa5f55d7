// tumble-sim: the extreme-motion bench in software. `run` writes one
// scenario's recordings, `bench` a whole calibration + rolling-cage bench,
// `live` plays a scenario in real time to UDP and a pty, `faults` rewrites a
// run with the network's and the serial line's faults.
#include <CLI/CLI.hpp>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "tools/sim/bench.hpp"
#include "tools/sim/fault_injector.hpp"
#include "tools/sim/live.hpp"
#include "tools/sim/live_sinks.hpp"
#include "tools/sim/run_writer.hpp"
#include "tumble_build_info.hpp"

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
               "writes (%llu dropped: pty full), %llu events late by > 1 ms (worst %.1f ms); MTi: %llu requests, "
               "%llu errors sent, %llu stream bytes held while not measuring, %llu bytes lost to a baud mismatch; "
               "%llu MSOP/DIFOP not sent while the lidar restarted, %llu IMU reads not sent while unplugged\n",
               s.stopped ? "stopped" : "done", static_cast<unsigned long long>(s.msop_packets),
               static_cast<unsigned long long>(s.difop_packets), static_cast<unsigned long long>(s.udp_send_failures),
               static_cast<unsigned long long>(s.imu_bytes), static_cast<unsigned long long>(s.imu_reads),
               static_cast<unsigned long long>(s.imu_bytes_dropped), static_cast<unsigned long long>(s.late_events),
               s.max_late_s * 1e3, static_cast<unsigned long long>(s.mti_requests),
               static_cast<unsigned long long>(s.mti_errors_sent), static_cast<unsigned long long>(s.imu_bytes_held),
               static_cast<unsigned long long>(s.imu_baud_mismatch_bytes),
               static_cast<unsigned long long>(s.lidar_restart_packets),
               static_cast<unsigned long long>(s.imu_unplugged_reads));
  return 0;
}

int command_faults(const std::string& run_dir, const std::string& out_dir, const FaultPlan& plan) {
  const FaultCounts c = inject_faults(run_dir, out_dir, plan);
  std::fprintf(stderr,
               "tumble-sim faults: wrote %s: of %llu MSOP packets %llu lost, %llu duplicated, %llu pairs swapped, "
               "%llu foreign added; %llu lidar datagrams in the gap, %llu clock-jumped, %llu late (mean %.1f ms, "
               "max %.1f ms), %llu stalled, %llu from a second lidar; of %llu IMU reads %llu in the gap, %llu garbled; "
               "%llu frames with a NaN rate\n",
               out_dir.c_str(), static_cast<unsigned long long>(c.msop_packets),
               static_cast<unsigned long long>(c.lidar_dropped), static_cast<unsigned long long>(c.lidar_duplicated),
               static_cast<unsigned long long>(c.lidar_swapped_pairs), static_cast<unsigned long long>(c.lidar_foreign),
               static_cast<unsigned long long>(c.lidar_gap_dropped),
               static_cast<unsigned long long>(c.lidar_clock_jumped), static_cast<unsigned long long>(c.lidar_delayed),
               c.lidar_mean_delay_s * 1e3, c.lidar_max_delay_s * 1e3, static_cast<unsigned long long>(c.lidar_stalled),
               static_cast<unsigned long long>(c.lidar_second_sender), static_cast<unsigned long long>(c.imu_reads),
               static_cast<unsigned long long>(c.imu_gap_dropped), static_cast<unsigned long long>(c.imu_garbled_reads),
               static_cast<unsigned long long>(c.imu_nan_frames));
  return 0;
}

// "C0:33" -> refuse MID 0xC0 with error 33.
void parse_refusal(const std::string& text, MtiDeviceOptions& mti) {
  const std::size_t colon = text.find(':');
  std::size_t mid_end = 0, code_end = 0;
  unsigned long mid = 0, code = 0;
  try {
    mid = std::stoul(text.substr(0, colon), &mid_end, 16);
    code = std::stoul(text.substr(colon + 1), &code_end, 10);
  } catch (const std::exception&) {
    mid_end = 0;
  }
  if (colon == std::string::npos || mid_end != colon || code_end != text.size() - colon - 1 || mid > 0xFF ||
      code > 0xFF)
    throw LiveError("--mti-refuse: '" + text + "' is not MID:CODE (hex MID, decimal code, e.g. C0:33)");
  mti.refuse_mid = static_cast<std::uint8_t>(mid);
  mti.refuse_code = static_cast<std::uint8_t>(code);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tumble-sim: the extreme-motion sensor bench in software (RS-16 lidar + MTi-30 IMU)", "tumble-sim"};
  // Fires while parsing, so it needs none of the required arguments.
  app.set_version_flag("--version", std::string("tumble-sim ") + tumble::kVersion)->trigger_on_parse();
  app.set_help_all_flag("--help-all", "Print the help of every subcommand and exit");
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
  bench->add_flag("--realistic", bench_options.realistic,
                  "bench2: every sensor error source on, the rig's lidar-IMU time offset, the cage's bars, "
                  "12 long out-and-back runs in the garage, corridor and yard, 12 runs with people, and 2 "
                  "long cage runs down the glass-ended hall with people, mixed pixels and network jitter");
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

  std::string mti_start = "measuring", mti_refuse;
  live->add_option("--mti-start", mti_start,
                   "the MTi when the host opens the port: measuring (streaming, as after power-up), config, or "
                   "wake-up (sends WakeUp, measures unless acknowledged within 0.5 s)")
      ->check(CLI::IsMember({"measuring", "config", "wake-up"}));
  live->add_flag("--mti-silent", live_options.mti.silent, "the MTi answers nothing and never streams");
  live->add_option("--mti-reply-delay", live_options.mti.reply_latency_s,
                   "seconds from a request to the MTi's answer (a late device)")
      ->check(CLI::NonNegativeNumber);
  live->add_option("--mti-product-code", live_options.mti.product_code, "what the MTi answers ReqProductCode with");
  live->add_flag("--start-when-measuring", live_options.start_when_measuring,
                 "start the run when the MTi first measures (with --mti-start config: once the host configured it)");
  live->add_option("--mti-refuse", mti_refuse,
                   "MID:CODE, e.g. C0:33: answer this request (hex MID) with Error 0x42 and this code");
  std::string lidar_restart, imu_unplug;
  CLI::Option* lidar_restart_option = live->add_option(
      "--lidar-restart", lidar_restart, "T,D: the lidar is off for D s from T s, then its header clock is a day behind");
  CLI::Option* imu_unplug_option = live->add_option(
      "--imu-unplug", imu_unplug, "T,D: the MTi is unplugged for D s from T s (the pty closed, then a new one)");
  live->add_option("--imu-link", live_options.imu_link,
                   "PATH: a symbolic link to the pty, re-pointed at each new one (announced instead of the pty)");
  FaultPlan fault_plan;
  std::string fault_run_dir, lidar_gap, imu_gap, clock_jump;
  CLI::App* faults = app.add_subcommand("faults", "rewrite a run folder with lidar and IMU faults (faults.yaml says which)");
  faults->add_option("RUN_DIR", fault_run_dir, "a `tumble-sim run` folder")->required();
  faults->add_option("OUT_DIR", out_dir, "output folder (created)")->required();
  faults->add_option("--seed", fault_plan.seed, "which packets and reads are hit (same seed, same bytes)");
  faults->add_option("--drop-lidar", fault_plan.drop_lidar, "chance an MSOP packet is lost");
  faults->add_option("--dup-lidar", fault_plan.dup_lidar, "chance an MSOP packet arrives twice");
  faults->add_option("--swap-lidar", fault_plan.swap_lidar, "chance an MSOP packet swaps places with the next");
  faults->add_option("--foreign-lidar", fault_plan.foreign_lidar,
                     "chance an MSOP packet is followed by one from 192.168.1.201");
  faults->add_option("--imu-garbage", fault_plan.imu_garbage, "chance a serial read is preceded by 1-40 garbage bytes");
  faults->add_option("--imu-nan", fault_plan.imu_nan, "chance a serial read's MTData2 frames carry a NaN rate of turn");
  double difop_change_at_s = 0.0;
  CLI::Option* difop_change_option = faults->add_option(
      "--difop-change", difop_change_at_s, "T: from T s on the lidar's DIFOPs carry vertical angles 5 % steeper");
  std::string second_lidar;
  CLI::Option* second_lidar_option =
      faults->add_option("--second-lidar", second_lidar,
                         "T,L: from T s on, 192.168.1.201 sends the lidar's stream from L s earlier, 1.5x as fast, "
                         "restamped to now");
  faults->add_option("--lidar-delay", fault_plan.lidar_delay_s,
                     "M: each lidar datagram is held an exponential time of mean M s, with stalls; order kept");
  CLI::Option* lidar_gap_option = faults->add_option("--lidar-gap", lidar_gap, "T,D: no lidar datagram for D s from T s");
  CLI::Option* imu_gap_option = faults->add_option("--imu-gap", imu_gap, "T,D: no serial read for D s from T s");
  std::string motor_stall;
  CLI::Option* motor_stall_option = faults->add_option(
      "--motor-stall", motor_stall, "T,D: the lidar's head stands still for D s from T s, its lasers firing on");
  CLI::Option* clock_jump_option =
      faults->add_option("--lidar-clock-jump", clock_jump, "T,S: lidar header times jump by S s from T s on");

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
      write_bench(bench_options.realistic ? plan_realistic_bench(bench_options.seed) : plan_bench(bench_options.seed),
                  out_dir, bench_options, std::cerr);
      return 0;
    }
    if (faults->parsed()) {
      if (lidar_gap_option->count() > 0) fault_plan.lidar_gap = parse_fault_window("--lidar-gap", lidar_gap);
      if (imu_gap_option->count() > 0) fault_plan.imu_gap = parse_fault_window("--imu-gap", imu_gap);
      if (motor_stall_option->count() > 0) fault_plan.motor_stall = parse_fault_window("--motor-stall", motor_stall);
      if (difop_change_option->count() > 0) fault_plan.difop_change_at_s = difop_change_at_s;
      if (second_lidar_option->count() > 0)
        fault_plan.second_lidar = parse_second_lidar("--second-lidar", second_lidar);
      if (clock_jump_option->count() > 0)
        fault_plan.lidar_clock_jump = parse_clock_jump("--lidar-clock-jump", clock_jump);
      return command_faults(fault_run_dir, out_dir, fault_plan);
    }
    if (live->parsed()) {
      if (live_duration->count() > 0) live_options.duration_s = live_duration_s;
      live_options.mti.start = *parse_mti_start_state(mti_start);
      if (!mti_refuse.empty()) parse_refusal(mti_refuse, live_options.mti);
      const auto outage = [](const char* option, const std::string& text) {
        const FaultWindow w = parse_fault_window(option, text);
        return LiveOutage{w.start_s, w.duration_s};
      };
      if (lidar_restart_option->count() > 0) live_options.lidar_restart = outage("--lidar-restart", lidar_restart);
      if (imu_unplug_option->count() > 0) live_options.imu_unplug = outage("--imu-unplug", imu_unplug);
      return command_live(scenario_from(scenario_path, live_seed, seed), live_options);
    }
  } catch (const std::exception& e) {
    std::cerr << "tumble-sim: " << e.what() << "\n";
    return 2;
  }
  return 2;
}
