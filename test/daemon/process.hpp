// Runs a program as a child process for tests: arguments, extra environment,
// captured stdout and stderr, exit status. No shell involved.
#pragma once

#include <string>
#include <vector>

namespace tumble::test {

struct ProcessResult {
  int exit_code = -1;  // -1: did not exit normally (killed by a signal)
  std::string out;
  std::string err;
};

// Runs argv[0] (a path) to completion.
ProcessResult run_process(const std::vector<std::string>& argv, const std::vector<std::string>& extra_env = {});

// Starts argv[0] with stdout and stderr going to the given files; returns its pid.
int spawn_process(const std::vector<std::string>& argv, const std::vector<std::string>& extra_env,
                  const std::string& out_path, const std::string& err_path);

// Waits for pid; returns its exit code, or -1 when a signal killed it.
int wait_process(int pid);

}  // namespace tumble::test
