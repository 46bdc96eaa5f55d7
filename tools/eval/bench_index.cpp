#include "tools/eval/bench_index.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include "tools/eval/text_fields.hpp"

namespace tumble::eval {

std::vector<BenchRun> read_bench_index(const std::filesystem::path& bench_dir) {
  const std::filesystem::path path = bench_dir / "bench.csv";
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open (not a tumble-sim bench directory?)");
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(path.string() + ": empty");
  const auto header = split_commas(line);
  const auto index_of = [&](std::string_view name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw std::runtime_error(path.string() + ":1: no column '" + std::string(name) + "'");
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t name_column = index_of("name");
  const std::size_t kind_column = index_of("kind");
  const std::size_t duration_column = index_of("duration_s");
  const std::size_t dir_column = index_of("dir");

  std::vector<BenchRun> runs;
  for (int line_number = 2; std::getline(in, line); ++line_number) {
    if (line.empty()) continue;
    const auto fields = split_commas(line);
    const auto where = [&] { return path.string() + ":" + std::to_string(line_number) + ": "; };
    if (fields.size() != header.size())
      throw std::runtime_error(where() + std::to_string(fields.size()) + " fields, header has " +
                               std::to_string(header.size()));
    BenchRun run;
    run.name = fields[name_column];
    run.kind = fields[kind_column];
    const std::optional<double> duration_s = parse_double(fields[duration_column]);
    if (!duration_s || !(*duration_s > 0.0))
      throw std::runtime_error(where() + "duration_s '" + std::string(fields[duration_column]) +
                               "' is not a positive number");
    run.duration_s = *duration_s;
    if (run.name.empty() || fields[dir_column].empty()) throw std::runtime_error(where() + "empty name or dir");
    run.dir = bench_dir / std::string(fields[dir_column]);
    runs.push_back(std::move(run));
  }
  if (runs.empty()) throw std::runtime_error(path.string() + ": no runs");
  return runs;
}

std::vector<BenchRun> select_runs(const std::vector<BenchRun>& runs, const RunFilter& filter) {
  const auto kind_selected = [&](const std::string& kind) {
    if (filter.kinds.empty()) return true;
    return std::any_of(filter.kinds.begin(), filter.kinds.end(), [&](const std::string& wanted) {
      return wanted == kind || (wanted == "cage" && kind == "rolling_cage");
    });
  };
  std::vector<BenchRun> selected;
  for (const BenchRun& run : runs)
    if (fnmatch(filter.name_glob.c_str(), run.name.c_str(), 0) == 0 && kind_selected(run.kind)) selected.push_back(run);
  return selected;
}

std::vector<std::string> kinds_of(const std::vector<BenchRun>& runs) {
  std::vector<std::string> kinds;
  for (const BenchRun& run : runs)
    if (std::find(kinds.begin(), kinds.end(), run.kind) == kinds.end()) kinds.push_back(run.kind);
  return kinds;
}

}  // namespace tumble::eval
