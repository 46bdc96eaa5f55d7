// spdlog set-up for tumbled: to stderr, with the level from daemon.log_level.
// Under systemd (stderr connected to the journal) lines carry a "<N>" syslog
// priority prefix, so `journalctl -p warning` works, and no timestamp (the
// journal adds one).
#pragma once

#include "daemon/config.hpp"

namespace tumble::daemon {

void configure_logging(LogLevel level);

}  // namespace tumble::daemon
