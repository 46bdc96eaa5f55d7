#include "tools/eval/child_processes.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace tumble::eval {
namespace {

std::string errno_text(int error) { return std::strerror(error); }

// The raw syscall: Debian 12's <sys/pidfd.h> (glibc 2.36) declares pidfd_open
// without C linkage, so C++ cannot link against it.
int open_pidfd(pid_t pid) { return static_cast<int>(syscall(SYS_pidfd_open, pid, 0)); }

// posix_spawn with stdout+stderr into log_path; returns the pid or an error text.
std::pair<pid_t, std::string> spawn(const ChildCommand& command) {
  if (command.argv.empty()) return {-1, "empty command"};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, command.log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::vector<char*> argv;
  for (const std::string& arg : command.argv) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int error = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) return {-1, "cannot start " + command.argv[0] + ": " + errno_text(error)};
  return {pid, ""};
}

}  // namespace

std::string ChildOutcome::describe() const {
  if (!start_error.empty()) return start_error;
  if (timed_out) return "killed after its " + std::to_string(static_cast<long>(wall_s)) + " s time limit";
  if (signal != 0) return "killed by signal " + std::to_string(signal) + " (" + strsignal(signal) + ")";
  return "exit code " + std::to_string(exit_code);
}

ChildPool::~ChildPool() {
  for (Child& child : children_) {
    kill(child.pid, SIGKILL);
    reap(child);
  }
}

void ChildPool::start(std::size_t id, const ChildCommand& command) {
  const auto now = std::chrono::steady_clock::now();
  auto [pid, error] = spawn(command);
  if (pid < 0) {
    ChildOutcome outcome;
    outcome.start_error = std::move(error);
    failed_starts_.emplace_back(id, std::move(outcome));
    return;
  }
  const int pidfd = open_pidfd(pid);
  if (pidfd < 0) {
    // Without a pidfd we could not wait for it alongside the others: stop it.
    const int open_error = errno;
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    ChildOutcome outcome;
    outcome.start_error = "pidfd_open: " + errno_text(open_error);
    failed_starts_.emplace_back(id, std::move(outcome));
    return;
  }
  const auto timeout =
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(command.timeout_s));
  children_.push_back(Child{id, pid, pidfd, now, now + timeout});
}

ChildOutcome ChildPool::reap(Child& child) {
  ChildOutcome outcome;
  int status = 0;
  rusage usage{};
  pid_t result;
  do {
    result = wait4(child.pid, &status, 0, &usage);
  } while (result < 0 && errno == EINTR);
  close(child.pidfd);
  outcome.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - child.started).count();
  if (result < 0) {
    outcome.start_error = "wait4: " + errno_text(errno);
    return outcome;
  }
  outcome.peak_rss_kib = usage.ru_maxrss;
  if (WIFEXITED(status)) outcome.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
  outcome.timed_out = child.killed_at_deadline;
  return outcome;
}

std::vector<std::pair<std::size_t, ChildOutcome>> ChildPool::wait(std::chrono::milliseconds max_wait) {
  std::vector<std::pair<std::size_t, ChildOutcome>> ended = std::move(failed_starts_);
  failed_starts_.clear();
  if (!ended.empty() || children_.empty()) return ended;

  auto now = std::chrono::steady_clock::now();
  auto wake = now + max_wait;
  for (const Child& child : children_)
    if (!child.killed_at_deadline) wake = std::min(wake, child.deadline);
  std::vector<pollfd> fds;
  for (const Child& child : children_) fds.push_back(pollfd{child.pidfd, POLLIN, 0});
  const auto wait_ms = std::chrono::duration_cast<std::chrono::milliseconds>(wake - now).count();
  const int ready = poll(fds.data(), fds.size(), static_cast<int>(std::max<long long>(0, wait_ms) + 1));
  if (ready < 0 && errno != EINTR) throw std::runtime_error("poll: " + errno_text(errno));

  now = std::chrono::steady_clock::now();
  std::vector<Child> still_running;
  for (std::size_t i = 0; i < children_.size(); ++i) {
    Child& child = children_[i];
    if (ready > 0 && (fds[i].revents & (POLLIN | POLLHUP)) != 0) {
      ended.emplace_back(child.id, reap(child));
      continue;
    }
    if (!child.killed_at_deadline && now >= child.deadline) {
      kill(child.pid, SIGKILL);
      child.killed_at_deadline = true;
    }
    still_running.push_back(child);
  }
  children_ = std::move(still_running);
  return ended;
}

ChildOutcome run_child(const ChildCommand& command) {
  ChildPool pool;
  pool.start(0, command);
  for (;;) {
    auto ended = pool.wait(std::chrono::seconds(1));
    if (!ended.empty()) return ended.front().second;
  }
}

}  // namespace tumble::eval
