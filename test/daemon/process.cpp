#include "test/daemon/process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace tumble::test {

namespace {

// In a cross-compiled tree the programs built there run under the emulator
// (CMAKE_CROSSCOMPILING_EMULATOR, space-separated), as ctest runs the tests
// themselves: without binfmt_misc the kernel cannot execute them. Other
// programs (systemd-analyze, /bin/sh) are this machine's own.
std::vector<std::string> command_line(const std::vector<std::string>& argv) {
#ifdef TUMBLE_TEST_EMULATOR
  if (argv.at(0).starts_with(TUMBLE_TEST_BINARY_DIR)) {
    std::vector<std::string> emulated;
    std::istringstream words(TUMBLE_TEST_EMULATOR);
    for (std::string word; words >> word;) emulated.push_back(word);
    emulated.insert(emulated.end(), argv.begin(), argv.end());
    return emulated;
  }
#endif
  return argv;
}

}  // namespace

int spawn_process(const std::vector<std::string>& program_argv, const std::vector<std::string>& extra_env,
                  const std::string& out_path, const std::string& err_path) {
  const std::vector<std::string> argv = command_line(program_argv);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::vector<std::string> env_strings(extra_env);
  for (char** e = environ; *e != nullptr; ++e) env_strings.emplace_back(*e);
  std::vector<char*> env;
  for (std::string& e : env_strings) env.push_back(e.data());
  env.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  // The child must not inherit a blocked SIGTERM/SIGINT from a test that blocks them.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK);
  pid_t pid = 0;
  const int error = posix_spawnp(&pid, args[0], &actions, &attributes, args.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (error != 0) throw std::runtime_error("posix_spawn " + argv[0] + " failed");
  return pid;
}

int wait_process(int pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

ProcessResult run_process(const std::vector<std::string>& argv, const std::vector<std::string>& extra_env) {
  const auto base = std::filesystem::temp_directory_path() / ("tumble_process_" + std::to_string(::getpid()));
  const std::string out_path = base.string() + ".out", err_path = base.string() + ".err";
  ProcessResult result;
  result.exit_code = wait_process(spawn_process(argv, extra_env, out_path, err_path));
  const auto slurp = [](const std::string& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    std::filesystem::remove(path);
    return text.str();
  };
  result.out = slurp(out_path);
  result.err = slurp(err_path);
  return result;
}

}  // namespace tumble::test
