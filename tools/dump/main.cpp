// tumble-dump: prints an RS-16 pcap or an MTi recording as CSV, or a summary
// of what the drivers counted. Exit codes: 0 clean, 1 unreadable or damaged
// recording (what could be decoded is still printed), 2 usage error.
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <map>
#include <stdexcept>
#include <string>

#include "drivers/rs16/lidar_datagram.hpp"
#include "tools/dump/mti_dump.hpp"
#include "tools/dump/rs16_dump.hpp"
#include "tumble_build_info.hpp"

namespace {

constexpr int kExitDamaged = 1;
constexpr int kExitUsage = 2;

void log_errors_only_to_stderr() {
  // The drivers log to spdlog's default (stdout) logger, which would mix into the CSV;
  // their warnings are counted and reported by this tool instead.
  auto logger = std::make_shared<spdlog::logger>("tumble-dump", std::make_shared<spdlog::sinks::stderr_sink_mt>());
  logger->set_level(spdlog::level::err);
  spdlog::set_default_logger(logger);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tumble-dump: print a recording as CSV (or --summary)", "tumble-dump"};
  // Fires while parsing, so it needs none of the required arguments.
  app.set_version_flag("--version", std::string("tumble-dump ") + tumble::kVersion)->trigger_on_parse();
  app.set_help_all_flag("--help-all", "Print the help of every subcommand and exit");
  app.require_subcommand(1);

  std::string rs16_path;
  tumble::dump::Rs16DumpOptions rs16;
  std::string source_ip;
  tumble::rs16::ClockMode clock = tumble::rs16::ClockMode::Synced;
  CLI::App* rs16_cmd = app.add_subcommand("rs16", "RS-16 pcap: one row per point of every assembled scan");
  rs16_cmd->add_option("file", rs16_path, "pcap/pcapng recording")->required();
  rs16_cmd->add_option("--split-azimuth-deg", rs16.driver.scans.split_azimuth_deg, "where scans split, [0, 360)")
      ->capture_default_str();
  rs16_cmd->add_option("--msop-port", rs16.source.msop_port, "UDP port of MSOP packets")->capture_default_str();
  rs16_cmd->add_option("--difop-port", rs16.source.difop_port, "UDP port of DIFOP packets")->capture_default_str();
  rs16_cmd->add_option("--source-ip", source_ip, "only packets from this lidar address");
  const std::map<std::string, tumble::rs16::ClockMode> clocks{{"synced", tumble::rs16::ClockMode::Synced},
                                                               {"free", tumble::rs16::ClockMode::Free}};
  rs16_cmd->add_option("--clock", clock, "synced: header time is host time; free: mapped from arrival times")
      ->transform(CLI::CheckedTransformer(clocks, CLI::ignore_case))
      ->default_str("synced");
  rs16_cmd->add_flag("--summary", rs16.summary, "print counts instead of rows");

  std::string mti_path;
  tumble::dump::MtiDumpOptions mti;
  CLI::App* mti_cmd = app.add_subcommand("mti", "MTi recording (pcap or raw Xbus bytes): one row per IMU sample");
  mti_cmd->add_option("file", mti_path, "recording")->required();
  mti_cmd->add_option("--baud", mti.stream.baud, "serial line speed")->capture_default_str();
  mti_cmd->add_option("--rate-hz", mti.stream.imu_rate_hz, "IMU output rate")->capture_default_str();
  mti_cmd->add_flag("--summary", mti.summary, "print counts instead of rows");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitUsage;
  }

  log_errors_only_to_stderr();
  static char buffer[1 << 16];
  std::setvbuf(stdout, buffer, _IOFBF, sizeof buffer);
  std::string problem;
  try {
    if (rs16_cmd->parsed()) {
      if (!source_ip.empty()) rs16.source.source_ip = tumble::rs16::parse_ipv4(source_ip);
      rs16.driver.decoder.clock = clock;
      problem = tumble::dump::dump_rs16(rs16_path, rs16, stdout);
    } else {
      problem = tumble::dump::dump_mti(mti_path, mti, stdout);
    }
  } catch (const std::invalid_argument& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "tumble-dump: %s\n", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "tumble-dump: %s\n", e.what());
    return kExitDamaged;
  }
  std::fflush(stdout);
  if (problem.empty()) return 0;
  std::fprintf(stderr, "tumble-dump: warning: %s\n", problem.c_str());
  return kExitDamaged;
}
