// Drawing with gnuplot (Debian gnuplot-nox): the script is kept next to the
// PNG it draws, so a figure can be re-drawn or restyled.
#pragma once

#include <filesystem>
#include <string>

namespace tumble::eval {

// Writes SCRIPT to SCRIPT_PATH and runs `gnuplot SCRIPT_PATH` (its output goes
// to SCRIPT_PATH with ".log"). Returns "" or why the plot could not be drawn.
std::string run_gnuplot(const std::string& script, const std::filesystem::path& script_path);

}  // namespace tumble::eval
