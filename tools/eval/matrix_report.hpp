// The matrix's outputs: per-cell statistics (model × de-skew), results.md
// and runs.csv.
//
// Statistics of a cell are over its ok runs only; diverged and failed runs
// are counted beside them (a lost estimate has no meaningful final error).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tools/eval/box_stats.hpp"
#include "tools/eval/run_result.hpp"

namespace tumble::eval {

struct CellSummary {
  Variant variant;
  std::size_t runs = 0;
  std::size_t ok = 0;
  std::size_t diverged = 0;
  std::size_t failed = 0;
  // Over ok runs; absent when there are none (or no run had an RPE segment).
  std::optional<BoxStats> translation_cm_per_m = std::nullopt;
  std::optional<BoxStats> rotation_deg_per_m = std::nullopt;
  std::optional<BoxStats> rpe_translation_cm_per_m = std::nullopt;
  std::optional<BoxStats> rpe_rotation_deg_per_m = std::nullopt;
};

// One summary per variant, in the given order.
std::vector<CellSummary> summarize_cells(const std::vector<RunResult>& results, const std::vector<Variant>& variants);

struct MatrixDescription {
  std::string bench_dir;
  std::string selection;  // the filters, as given
  std::size_t runs = 0;   // bench runs evaluated
  EvalOptions options;
  std::string box_plot_file;  // "" when no plot was drawn
};

std::string results_markdown(const MatrixDescription& description, const std::vector<CellSummary>& cells,
                             const std::vector<RunResult>& results);

// One row per job; numbers empty when not measured. Columns are only ever
// appended (scripts read them by header). Throws std::runtime_error
// when the file cannot be written.
void write_runs_csv(const std::filesystem::path& path, const std::vector<RunResult>& results);

}  // namespace tumble::eval
