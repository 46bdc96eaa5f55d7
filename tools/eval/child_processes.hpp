// Child processes run N at a time: spawned with posix_spawn (stdin from
// /dev/null, stdout and stderr into a log file), watched through pidfds, reaped
// with wait4() for their peak RSS, and killed when they overrun a deadline.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace tumble::eval {

struct ChildCommand {
  std::vector<std::string> argv;  // argv[0]: a path, or a name looked up in PATH
  std::filesystem::path log_path;
  double timeout_s = 600.0;
};

struct ChildOutcome {
  std::string start_error;  // non-empty: the process never ran (bad path, log not writable)
  int exit_code = -1;       // when it exited normally
  int signal = 0;           // when a signal ended it
  bool timed_out = false;   // killed by us at its deadline
  double wall_s = 0.0;
  long peak_rss_kib = 0;

  bool succeeded() const { return start_error.empty() && signal == 0 && exit_code == 0; }
  // "exit code 3", "killed by signal 9 (timed out after 600 s)", the start error...
  std::string describe() const;
};

class ChildPool {
 public:
  ChildPool() = default;
  ChildPool(const ChildPool&) = delete;
  ChildPool& operator=(const ChildPool&) = delete;
  ~ChildPool();  // kills and reaps whatever still runs

  // A child that cannot be started is reported by the next wait() with its start_error.
  void start(std::size_t id, const ChildCommand& command);
  std::size_t running() const { return children_.size() + failed_starts_.size(); }

  // Blocks until at least one child has ended or `max_wait` has passed; returns
  // the ended ones (id, outcome).
  std::vector<std::pair<std::size_t, ChildOutcome>> wait(std::chrono::milliseconds max_wait);

 private:
  struct Child {
    std::size_t id;
    pid_t pid;
    int pidfd;
    std::chrono::steady_clock::time_point started;
    std::chrono::steady_clock::time_point deadline;
    bool killed_at_deadline = false;
  };
  ChildOutcome reap(Child& child);

  std::vector<Child> children_;
  std::vector<std::pair<std::size_t, ChildOutcome>> failed_starts_;
};

// One child, waited for (e.g. gnuplot).
ChildOutcome run_child(const ChildCommand& command);

}  // namespace tumble::eval
