#include "tools/calib/rig_command.hpp"

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <map>
#include <string>

#include "tools/calib/input_error.hpp"
#include "tools/calib/rig_calibration.hpp"
#include "tools/calib/rig_report.hpp"

namespace tumble::calib {

int run_rig_command(int argc, char** argv) {
  CLI::App app{
      "tumble-calib rig: the lidar-IMU rotation, time offset and lever arm from a recording of both sensors "
      "(lidar.pcap + imu.pcap, e.g. tumbled --record)"};
  app.name("tumble-calib rig");
  std::string dir;
  RigOptions options;
  app.add_option("RECORDING_DIR", dir, "folder with lidar.pcap and imu.pcap (manifest.yaml, if any, gives the IMU line)")
      ->required();
  app.add_option("--imu-rate-hz", options.imu_rate_hz, "IMU output rate when there is no manifest.yaml (default 100)")
      ->check(CLI::Range(1.0, 1000.0));
  app.add_option("--imu-baud", options.imu_baud, "IMU baud rate when there is no manifest.yaml (default 115200)")
      ->check(CLI::Range(9600u, 4000000u));
  app.add_option("--lidar-clock", options.lidar_clock,
                 "the lidar's header clock when there is no manifest.yaml: free (tumbled's default: mapped to the "
                 "recorded arrival times) or synced (PTP/GPS UTC)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, rs16::ClockMode>{{"free", rs16::ClockMode::Free}, {"synced", rs16::ClockMode::Synced}}));
  app.add_option("--max-offset-s", options.max_offset_s, "search the time offset within +-this (default 0.3)")
      ->check(CLI::Range(0.01, 1.0));
  app.add_option("--max-passes", options.max_deskewed_passes,
                 "de-skewed registration passes at most; they end when the estimate settles (default 6)")
      ->check(CLI::Range(1, 20));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  spdlog::set_level(spdlog::level::err);
  try {
    const RigCalibration c = calibrate_rig(dir, options, [](const RigPass& pass) {
      print_rig_pass(stdout, pass);
      std::fflush(stdout);
    });
    print_rig_calibration(stdout, c);
  } catch (const InputError& e) {
    std::fprintf(stderr, "tumble-calib rig: %s\n", e.what());
    return 2;
  } catch (const RigError& e) {
    std::fprintf(stderr, "tumble-calib rig: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace tumble::calib
