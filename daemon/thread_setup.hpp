// Per-thread setup for the pipeline threads: a name for top/gdb, and the
// optional real-time priority (daemon.realtime_priority) of the threads on
// the IMU -> TUMBLE_ODOM path, and the lower priority of the registration
// thread (daemon.registration_nice).
#pragma once

#include <string>

namespace tumble::daemon {

// Linux thread names are at most 15 characters; longer names are cut.
void name_this_thread(const std::string& name);

// SCHED_FIFO at `priority` (1..99) for the calling thread; 0 leaves the
// normal scheduler. Returns an error message, empty on success.
std::string set_realtime_priority(int priority);

// Adds `increment` (0..19) to the calling thread's nice value (Linux nice is
// per thread); 0 leaves it. Returns an error message, empty on success.
std::string lower_this_thread_priority(int increment);

}  // namespace tumble::daemon
