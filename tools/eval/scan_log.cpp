#include "tools/eval/scan_log.hpp"

#include <algorithm>
#include <fstream>
#include <stdexcept>

#include "tools/eval/text_fields.hpp"

namespace tumble::eval {

const std::vector<double>& ScanLog::column(const std::string& name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  if (it == columns.end()) throw std::runtime_error("scan log has no column '" + name + "'");
  return values[static_cast<std::size_t>(it - columns.begin())];
}

bool ScanLog::has_column(const std::string& name) const {
  return std::find(columns.begin(), columns.end(), name) != columns.end();
}

std::vector<std::string> ScanLog::stage_columns() const {
  std::vector<std::string> stages;
  for (const std::string& name : columns)
    if (name.size() > 3 && name.ends_with("_ms") && name != "total_ms" && name != "latency_ms") stages.push_back(name);
  return stages;
}

ScanLog read_scan_log(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  ScanLog log;
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(path.string() + ": empty (no header line)");
  for (const std::string_view name : split_commas(line)) log.columns.emplace_back(name);
  log.values.resize(log.columns.size());
  for (int line_number = 2; std::getline(in, line); ++line_number) {
    if (line.empty()) continue;
    const auto fields = split_commas(line);
    const auto where = [&] { return path.string() + ":" + std::to_string(line_number) + ": "; };
    if (fields.size() != log.columns.size())
      throw std::runtime_error(where() + std::to_string(fields.size()) + " fields, header has " +
                               std::to_string(log.columns.size()));
    for (std::size_t i = 0; i < fields.size(); ++i) {
      std::optional<double> value = parse_double(fields[i]);
      if (fields[i] == "true") value = 1.0;
      if (fields[i] == "false") value = 0.0;
      if (!value)
        throw std::runtime_error(where() + log.columns[i] + " '" + std::string(fields[i]) + "' is not a number");
      log.values[i].push_back(*value);
    }
  }
  if (in.bad()) throw std::runtime_error(path.string() + ": read error");
  return log;
}

}  // namespace tumble::eval
