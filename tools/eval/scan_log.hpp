// tumbled's --scan-log CSV, read by column name (the stage columns follow the
// pipeline's stages, so they are discovered, not hard-coded): every column
// named "<stage>_ms" other than total_ms and latency_ms is a stage.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tumble::eval {

struct ScanLog {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> values;  // values[column][scan]; booleans as 0/1

  std::size_t scans() const { return values.empty() ? 0 : values.front().size(); }
  // Throws std::runtime_error naming the column when it is absent.
  const std::vector<double>& column(const std::string& name) const;
  bool has_column(const std::string& name) const;
  std::vector<std::string> stage_columns() const;
};

// Throws std::runtime_error "FILE:LINE: why" (missing header, wrong field
// count, a field that is not a number or true/false).
ScanLog read_scan_log(const std::filesystem::path& path);

}  // namespace tumble::eval
