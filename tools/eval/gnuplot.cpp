#include "tools/eval/gnuplot.hpp"

#include <fstream>

#include "tools/eval/child_processes.hpp"

namespace tumble::eval {

std::string run_gnuplot(const std::string& script, const std::filesystem::path& script_path) {
  {
    std::ofstream out(script_path);
    out << script;
    if (!out) return script_path.string() + ": cannot write";
  }
  std::filesystem::path log_path = script_path;
  log_path += ".log";
  ChildCommand command;
  command.argv = {"gnuplot", script_path.string()};
  command.log_path = log_path;
  command.timeout_s = 120.0;
  const ChildOutcome outcome = run_child(command);
  if (!outcome.succeeded())
    return "gnuplot: " + outcome.describe() + " (see " + log_path.string() + "; Debian package gnuplot-nox)";
  return "";
}

}  // namespace tumble::eval
