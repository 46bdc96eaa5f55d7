// Degrees and radians, for configuration files and reports that speak degrees.
#pragma once

#include <numbers>

namespace tumble {

inline constexpr double kDegToRad = std::numbers::pi / 180.0;
inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;

}  // namespace tumble
