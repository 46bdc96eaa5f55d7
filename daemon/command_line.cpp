#include "daemon/command_line.hpp"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <system_error>

#include "tumble_build_info.hpp"

namespace tumble::daemon {

ReplayRate parse_replay_rate(const std::string& text) {
  if (text == "max") return {true, 1.0};
  double factor = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, factor);
  if (ec != std::errc() || ptr != end || !std::isfinite(factor) || factor <= 0.0)
    throw UsageError(fmt::format("--rate: \"{}\" is neither max nor a positive speed factor (1 = real time)", text));
  return {false, factor};
}

CommandLine parse_command_line(const std::vector<std::string>& args) {
  CLI::App app{"tumbled: lidar-inertial odometry daemon (RS-16 + MTi-30 -> LCM)", "tumbled"};
  // Fires while parsing, so it needs none of the required arguments.
  app.set_version_flag("--version", std::string("tumbled ") + kVersion)->trigger_on_parse();
  app.footer(
      "Live by default: reads the lidar's UDP packets and the IMU's serial port as configured.\n\n"
      "Exit status:\n"
      "  0 clean stop, 1 runtime failure, 2 bad configuration or command line.");
  // Room for the longest option and its notes, so help2man finds where each description starts.
  app.get_formatter()->column_width(40);

  CommandLine out;
  std::string config_path, rate, trajectory_out, scan_log, model, lcm_url, log_level, record_dir;
  std::vector<std::string> settings;
  std::vector<std::string> replay;
  app.add_option("--config", config_path,
                 fmt::format("YAML configuration file (default: {} where it exists, else the compiled defaults)",
                             kSystemConfigPath))
      ->check(CLI::ExistingFile);
  auto* replay_option =
      app.add_option("--replay", replay, "replay a lidar pcap and an IMU pcap instead of live sensors")
          ->expected(2)
          ->type_name("LIDAR.pcap IMU.pcap")
          ->check(CLI::ExistingFile);
  auto* rate_option =
      app.add_option("--rate", rate, "replay speed: 1 (real time), N (N times faster) or max")->needs(replay_option);
  auto* trajectory_option =
      app.add_option("--trajectory-out", trajectory_out, "write registered scan poses (TUM format) to FILE");
  auto* scan_log_option =
      app.add_option("--scan-log", scan_log, "write one CSV row per registered scan (quality, stage times) to FILE");
  app.add_option("--set", settings, "set any configuration key, e.g. --set map.radius_m=30 (repeatable)")
      ->type_name("KEY=VALUE");
  auto* record_option = app.add_option("--record", record_dir, "record the live sensors' bytes into DIR (record.dir)")
                            ->excludes(replay_option);
  auto* url_option = app.add_option("--lcm-url", lcm_url, "LCM URL (lcm.url)");
  auto* model_option = app.add_option("--model", model, "point weight model NM|TW|VTW|GVTW|SAW (registration.model)");
  bool deskew_flag = false, no_deskew_flag = false;
  auto* deskew = app.add_flag("--deskew", deskew_flag, "de-skew scans (registration.deskew: true)");
  app.add_flag("--no-deskew", no_deskew_flag, "do not de-skew scans (registration.deskew: false)")->excludes(deskew);
  auto* level_option =
      app.add_option("--log-level", log_level, "trace|debug|info|warn|error|critical|off (daemon.log_level)");
  app.add_flag("--print-config", out.print_config, "print the effective configuration as YAML and exit");

  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const CLI::CallForHelp&) {
    out.help = app.help();
    return out;
  } catch (const CLI::CallForVersion& e) {
    out.help = e.what();
    out.help += "\n";
    return out;
  } catch (const CLI::ParseError& e) {
    throw UsageError(e.what());
  }

  if (!config_path.empty()) out.config_path = config_path;
  if (replay_option->count() > 0) out.replay = ReplayFiles{replay.at(0), replay.at(1)};
  if (rate_option->count() > 0) out.rate = parse_replay_rate(rate);
  if (trajectory_option->count() > 0) out.trajectory_out = trajectory_out;
  if (scan_log_option->count() > 0) out.scan_log = scan_log;
  for (const std::string& setting : settings) {
    const std::size_t equals = setting.find('=');
    if (equals == std::string::npos || equals == 0)
      throw UsageError("--set " + setting + ": expected KEY=VALUE, e.g. --set map.radius_m=30");
    out.overrides.push_back({setting.substr(0, equals), setting.substr(equals + 1)});
  }
  if (record_option->count() > 0) out.overrides.push_back({"record.dir", record_dir});
  if (url_option->count() > 0) out.overrides.push_back({"lcm.url", lcm_url});
  if (model_option->count() > 0) out.overrides.push_back({"registration.model", model});
  if (deskew_flag) out.overrides.push_back({"registration.deskew", "true"});
  if (no_deskew_flag) out.overrides.push_back({"registration.deskew", "false"});
  if (level_option->count() > 0) out.overrides.push_back({"daemon.log_level", log_level});
  return out;
}

void use_system_config_unless_given(CommandLine& command_line, const std::filesystem::path& system_config_path) {
  if (command_line.config_path) return;
  std::error_code ignored;
  if (std::filesystem::exists(system_config_path, ignored)) command_line.config_path = system_config_path.string();
}

std::string config_origin(const CommandLine& command_line) {
  return command_line.config_path.value_or("compiled defaults");
}

DaemonConfig effective_config(const CommandLine& command_line) {
  if (command_line.config_path) return load_config_file(*command_line.config_path, command_line.overrides);
  return default_config(command_line.overrides);
}

}  // namespace tumble::daemon
