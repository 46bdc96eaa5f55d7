// The calibration's outputs: residuals.csv (one row per scan), bins.csv (one
// row per speed bin: the figure's data and the check), calib.yaml (the
// snippet for config/tumbled.yaml) and the printed summary.
#pragma once

#include <cstdio>
#include <filesystem>
#include <span>
#include <string>

#include "tools/calib/axis_calibration.hpp"
#include "tools/calib/run_evaluation.hpp"

namespace tumble::calib {

struct Calibration {
  std::string bench;        // as given on the command line
  AxisCalibration linear;   // rail
  AxisCalibration angular;  // turntable
  bool has_linear = false;
  bool has_angular = false;
};

// Throw std::runtime_error naming the file when it cannot be written.
void write_residuals_csv(const std::filesystem::path& path, std::span<const RunOutcome> runs,
                         const Calibration& calibration, std::span<const double> rail_centres,
                         std::span<const double> turntable_centres);
void write_bins_csv(const std::filesystem::path& path, const Calibration& calibration);
void write_calib_yaml(const std::filesystem::path& path, const Calibration& calibration);

// Fitted parameters beside the paper's, the bins and the check.
void print_summary(std::FILE* out, const Calibration& calibration);

}  // namespace tumble::calib
