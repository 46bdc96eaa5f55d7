// Runs the tumble-dump binary and captures its exit code, stdout and stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace tumble::test {

struct DumpRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream f(path);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// A file under the temp directory, named for this process and a tag, removed on destruction.
struct TempFile {
  explicit TempFile(const std::string& tag)
      : path(std::filesystem::temp_directory_path() /
             ("tumble-dump-test-" + std::to_string(::getpid()) + "-" + tag)) {}
  ~TempFile() { std::filesystem::remove(path); }
  std::filesystem::path path;
};

// args are single-quoted for the shell; none of ours contains a quote.
inline DumpRun run_dump(const std::vector<std::string>& args) {
  const TempFile err_file("stderr");
  std::string command = TUMBLE_DUMP_EMULATOR "'" TUMBLE_DUMP_EXE "'";
  for (const std::string& a : args) command += " '" + a + "'";
  command += " 2>'" + err_file.path.string() + "'";
  DumpRun run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[1 << 16];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) run.out.append(buffer, n);
  const int status = ::pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.err = read_text(err_file.path);
  return run;
}

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream s(text);
  for (std::string line; std::getline(s, line);) lines.push_back(line);
  return lines;
}

inline std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream s(line);
  while (std::getline(s, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

}  // namespace tumble::test
