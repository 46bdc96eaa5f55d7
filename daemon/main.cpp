// tumbled: parse the command line and configuration, then run the daemon.
// Exit codes: 0 clean stop, 1 runtime failure, 2 bad configuration or command line.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <csignal>
#include <exception>
#include <string>
#include <vector>

#include "daemon/command_line.hpp"
#include "daemon/config.hpp"
#include "daemon/logging.hpp"
#include "daemon/main_loop.hpp"
#include "daemon/run.hpp"
#include "daemon/sensor_parts.hpp"
#include "tumble_build_info.hpp"

int main(int argc, char** argv) {
  using namespace tumble::daemon;
  std::signal(SIGPIPE, SIG_IGN);  // a closed socket is an error return, not a reason to die

  CommandLine command_line;
  DaemonConfig config;
  try {
    command_line = parse_command_line(std::vector<std::string>(argv, argv + argc));
    if (!command_line.help.empty()) {
      fmt::print("{}", command_line.help);
      return 0;
    }
    use_system_config_unless_given(command_line, tumble::kSystemConfigPath);
    config = effective_config(command_line);
  } catch (const UsageError& e) {
    fmt::print(stderr, "tumbled: {} (see tumbled --help)\n", e.what());
    return 2;
  } catch (const ConfigError& e) {
    fmt::print(stderr, "tumbled: {}\n", e.what());
    return 2;
  }
  if (command_line.print_config) {
    fmt::print("{}", to_yaml(config));
    return 0;
  }

  try {
    ShutdownSignals signals;  // before any thread starts (the logger's too), so every thread inherits the mask
    const AsyncLogging logging(config.daemon.log_level);
    spdlog::info("tumbled {}: configuration from {}", tumble::kVersion, config_origin(command_line));
    try {
      lcm::LCM lcm(config.lcm.url);
      if (!lcm.good()) {
        spdlog::error("lcm.url: LCM cannot start on {}", config.lcm.url);
        return 1;
      }
      return run_daemon(config, run_options(command_line), lcm, signals, make_sensor_parts);
    } catch (const std::exception& e) {
      spdlog::critical("{}", e.what());
      return 1;
    }
  } catch (const std::exception& e) {  // before logging started
    fmt::print(stderr, "tumbled: {}\n", e.what());
    return 1;
  }
}
