// The paper's figure (§V-A, Fig. 5) for one axis, drawn by gnuplot into a
// PNG: top, the measured mean residual against speed (median, first–third
// quartile band, the noise at rest dotted); bottom, the same in speed
// uncertainty: the third quartiles that were fitted (noise removed), the
// fitted curve, and the noise-free de-skew error from the ground truth
// (median and third quartile) it is meant to predict. The gnuplot script
// (data inline) is kept beside the PNG.
#pragma once

#include <filesystem>
#include <string>

#include "tools/calib/axis_calibration.hpp"

namespace tumble::calib {

// The script that draws `png`.
std::string plot_script(const AxisCalibration& axis, const std::filesystem::path& png);

// Writes `script_path` and runs gnuplot on it. Throws std::runtime_error
// when the script cannot be written or gnuplot fails (or is not installed).
void draw_plot(const AxisCalibration& axis, const std::filesystem::path& png, const std::filesystem::path& script_path);

}  // namespace tumble::calib
