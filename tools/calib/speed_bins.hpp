// Binning scans by speed and the quartiles drawn per bin (paper Fig. 5:
// median and first/third quartiles against speed).
//
// Bins are centred on the bench's nominal speeds (|nominal_speed| of its
// runs) plus 0; a scan goes to the centre nearest its TRUE mean speed
// (edges halfway between centres). Runs accelerate and brake, so a scan is
// binned by the speed it was taken at, not by its run's label; the static
// start and end of every run fill the zero-speed bin, whose residual is the
// paper's noise offset.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace tumble::calib {

struct Quartiles {
  double q1 = 0;
  double median = 0;
  double q3 = 0;
};

// Linear interpolation between order statistics (Hyndman–Fan type 7, as R,
// NumPy and gnuplot use). Throws std::invalid_argument on an empty input.
Quartiles quartiles(std::vector<double> values);
double median(std::vector<double> values);

// 0 and the distinct |speeds|, ascending.
std::vector<double> bin_centres(std::span<const double> nominal_speeds);
// Index of the centre nearest |speed| (ties: the lower one). centres must be
// ascending and non-empty.
std::size_t bin_of(std::span<const double> centres, double speed);

}  // namespace tumble::calib
