// The paper's figure of final pose errors: box plots per model, left
// without de-skewing, right with it; translation (cm/m) on top, rotation
// (deg/m) below. Drawn by gnuplot (Debian gnuplot-nox, pngcairo) from a
// script that carries its own data, kept next to the PNG so it can be
// re-drawn or restyled. Boxes are the precomputed BoxStats (Q1–Q3, median
// line, Tukey whiskers, outliers as circles), so the plot shows exactly the
// numbers of the table.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tools/eval/matrix_report.hpp"

namespace tumble::eval {

std::string box_plot_script(const std::vector<CellSummary>& cells, const std::filesystem::path& png_path);

// Writes SCRIPT_PATH and runs `gnuplot SCRIPT_PATH` (output into
// SCRIPT_PATH with ".log"). Returns "" or why the plot could not be drawn.
std::string draw_box_plot(const std::vector<CellSummary>& cells, const std::filesystem::path& script_path,
                          const std::filesystem::path& png_path);

}  // namespace tumble::eval
