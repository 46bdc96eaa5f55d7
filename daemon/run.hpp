// What tumbled does between parsing its configuration and exiting: build the
// pipeline from the parts the drivers and the core provide, publish, report
// status and health, talk to systemd, and stop cleanly on SIGINT/SIGTERM
// (within a second) or at the end of a replay (exit code 0), or when a thread
// fails or live input ends (exit code 1, so that systemd restarts tumbled).
#pragma once

#include <boost/asio/io_context.hpp>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <string>

#include "daemon/command_line.hpp"
#include "daemon/config.hpp"
#include "daemon/main_loop.hpp"
#include "daemon/pipeline.hpp"

namespace tumble::daemon {

struct RunOptions {
  std::optional<ReplayFiles> replay;
  ReplayRate rate;
  std::optional<std::string> trajectory_out;
  std::optional<std::string> scan_log;
};

RunOptions run_options(const CommandLine& command_line);

// Builds the sources, decoders, stages and recorder for this run; live
// sources use the pipeline's io_context.
using PartsFactory =
    std::function<PipelineParts(boost::asio::io_context& io, const DaemonConfig& config, const RunOptions& options)>;

// Blocks until the daemon stops; returns the exit code (0 clean stop, 1 failure).
// `signals` must have been constructed before any thread was started.
int run_daemon(const DaemonConfig& config, const RunOptions& options, lcm::LCM& lcm, ShutdownSignals& signals,
               const PartsFactory& make_parts);

}  // namespace tumble::daemon
