// spdlog set-up for tumbled: to stderr, with the level from daemon.log_level.
// Under systemd (stderr connected to the journal) lines carry a "<N>" syslog
// priority prefix, so `journalctl -p warning` works, and no timestamp (the
// journal adds one).
//
// A log call on the io, fuser or publish thread (SCHED_FIFO) must never wait
// for stderr (a slow journal, a full pipe): lines go through a queue to one
// logging thread, and a full queue drops its oldest line. Construct it after
// the signal mask is set (its thread inherits the mask); its destructor
// writes out what is queued, and nothing may log after it.
#pragma once

#include <cstddef>

#include "daemon/config.hpp"

namespace tumble::daemon {

class AsyncLogging {
 public:
  static constexpr std::size_t kQueueLines = 8192;

  explicit AsyncLogging(LogLevel level);
  ~AsyncLogging();
  AsyncLogging(const AsyncLogging&) = delete;
  AsyncLogging& operator=(const AsyncLogging&) = delete;
};

}  // namespace tumble::daemon
