// tumbled's command line (CLI11). Flags that set configuration keys become
// ConfigOverrides, so they pass the same validation as the file and win over it.
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "daemon/config.hpp"

namespace tumble::daemon {

// A bad command line; the message is one line. tumbled exits with code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Replay pacing: `max` runs as fast as the pipeline goes, without dropping
// anything; otherwise `factor` times real time (1 = as the sensors sent it).
struct ReplayRate {
  bool max = false;
  double factor = 1.0;
  bool operator==(const ReplayRate&) const = default;
};

struct ReplayFiles {
  std::string lidar_pcap;
  std::string imu_pcap;
  bool operator==(const ReplayFiles&) const = default;
};

struct CommandLine {
  std::optional<std::string> config_path;  // none: the compiled defaults (= config/tumbled.yaml)
  std::optional<ReplayFiles> replay;
  ReplayRate rate;
  std::optional<std::string> trajectory_out;  // TUM-format file of registered scan poses
  std::optional<std::string> scan_log;        // CSV of per-scan registration figures
  bool print_config = false;
  std::vector<ConfigOverride> overrides;  // --set, --model, --deskew, --lcm-url, --log-level, --record
  std::string help;                       // --help given: print this and exit 0
};

// args[0] is the program name. Throws UsageError.
CommandLine parse_command_line(const std::vector<std::string>& args);

// Without --config, the system configuration file is read where it exists:
// sets config_path to system_config_path then (tumbled passes
// kSystemConfigPath, /etc/tumble/tumbled.yaml for the package).
void use_system_config_unless_given(CommandLine& command_line, const std::filesystem::path& system_config_path);

// What tumbled logs at start: the configuration file's path, or "compiled defaults".
std::string config_origin(const CommandLine& command_line);

// Defaults < config file < flags. Throws ConfigError.
DaemonConfig effective_config(const CommandLine& command_line);

// "max" or a positive factor ("1", "4", "0.5"). Throws UsageError.
ReplayRate parse_replay_rate(const std::string& text);

}  // namespace tumble::daemon
