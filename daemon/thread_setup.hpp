// Per-thread setup for the pipeline threads: a name for top/gdb, and the
// optional real-time priority (daemon.realtime_priority).
#pragma once

#include <string>

namespace tumble::daemon {

// Linux thread names are at most 15 characters; longer names are cut.
void name_this_thread(const std::string& name);

// SCHED_FIFO at `priority` (1..99) for the calling thread; 0 leaves the
// normal scheduler. Returns an error message, empty on success.
std::string set_realtime_priority(int priority);

}  // namespace tumble::daemon
