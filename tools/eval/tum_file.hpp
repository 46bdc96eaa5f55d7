// TUM trajectory files: "t x y z qx qy qz qw" per line, '#' comments. What
// tumbled's --trajectory-out and tumble-sim's ground_truth.tum write, and what
// evo and the TUM tools read.
#pragma once

#include <filesystem>

#include "tools/eval/pose_series.hpp"

namespace tumble::eval {

// Throws std::runtime_error "FILE:LINE: why" on a malformed line, a
// non-unit quaternion, or times that do not increase; "FILE: ..." when the
// file cannot be opened.
PoseSeries read_tum(const std::filesystem::path& path);

void write_tum(const std::filesystem::path& path, const PoseSeries& series);

}  // namespace tumble::eval
