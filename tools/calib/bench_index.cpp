#include "tools/calib/bench_index.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "tools/calib/input_error.hpp"

namespace tumble::calib {
namespace {

constexpr const char* kHeader = "name,kind,nominal_speed,speed_unit,duration_s,dir";

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream stream(line);
  std::string field;
  while (std::getline(stream, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

// Strict: the whole field must be a finite number.
bool parse_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(value);
}

std::string strip_cr(std::string line) {
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

}  // namespace

Rig rig_from_kind(const std::string& kind) {
  if (kind == "rail") return Rig::Rail;
  if (kind == "turntable") return Rig::Turntable;
  return Rig::Other;
}

BenchIndex read_bench_index(const std::filesystem::path& bench_dir) {
  const std::filesystem::path path = bench_dir / "bench.csv";
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot be opened (is " + bench_dir.string() + " a tumble-sim bench?)");
  std::string line;
  if (!std::getline(in, line) || strip_cr(line) != kHeader)
    throw InputError(path.string() + ":1: header is not \"" + kHeader + "\"");

  BenchIndex index;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    line = strip_cr(line);
    if (line.empty()) continue;
    const std::string where = "bench.csv:" + std::to_string(line_number) + ": ";
    const std::vector<std::string> f = split_csv(line);
    if (f.size() != 6) {
      index.problems.push_back(where + std::to_string(f.size()) + " fields, expected 6; row skipped");
      continue;
    }
    BenchRun run;
    run.name = f[0];
    run.kind = f[1];
    run.rig = rig_from_kind(f[1]);
    run.speed_unit = f[3];
    if (run.name.empty() || f[5].empty()) {
      index.problems.push_back(where + "empty name or dir; row skipped");
      continue;
    }
    if (!parse_number(f[2], run.nominal_speed)) {
      index.problems.push_back(where + "nominal_speed \"" + f[2] + "\" is not a number; row skipped");
      continue;
    }
    if (!parse_number(f[4], run.duration_s) || run.duration_s <= 0) {
      index.problems.push_back(where + "duration_s \"" + f[4] + "\" is not a positive number; row skipped");
      continue;
    }
    const char* expected_unit = run.rig == Rig::Rail ? "m/s" : run.rig == Rig::Turntable ? "rad/s" : nullptr;
    if (expected_unit != nullptr && run.speed_unit != expected_unit) {
      index.problems.push_back(where + run.kind + " run with speed_unit \"" + run.speed_unit + "\", expected " +
                               expected_unit + "; row skipped");
      continue;
    }
    run.dir = bench_dir / f[5];
    index.runs.push_back(std::move(run));
  }
  return index;
}

}  // namespace tumble::calib
