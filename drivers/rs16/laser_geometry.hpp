// Vertical angles of the 16 lasers and the polar-to-Cartesian model of
// docs/sensors.md: x forward, y left, z up, optical centre R off the rotation axis.
#pragma once

#include <array>
#include <string_view>

#include "drivers/rs16/packet_layout.hpp"

namespace tumble::rs16 {

inline constexpr double kOpticalCentreOffset_m = 0.03825;

// Design values for lasers 0..15, used until the first DIFOP.
inline constexpr std::array<double, kLasers> kDesignVerticalAnglesDeg{-15, -13, -11, -9, -7, -5, -3, -1,
                                                                      15,  13,  11,  9,  7,  5,  3,  1};

enum class AngleSource { Design, Config, Difop };
std::string_view to_string(AngleSource source);

struct LaserTable {
  AngleSource source = AngleSource::Design;
  std::array<double, kLasers> vertical_deg = kDesignVerticalAnglesDeg;
  std::array<double, kLasers> cos_vertical{};
  std::array<double, kLasers> sin_vertical{};
};

LaserTable make_laser_table(const std::array<double, kLasers>& vertical_deg, AngleSource source);

struct PointXyz {
  double x_m, y_m, z_m;
};

// cos/sin of the azimuth are passed in so the caller can share them across lasers.
inline PointXyz to_cartesian(double distance_m, double cos_vertical, double sin_vertical, double cos_azimuth,
                             double sin_azimuth) {
  const double horizontal_m = distance_m * cos_vertical + kOpticalCentreOffset_m;
  return {horizontal_m * cos_azimuth, -horizontal_m * sin_azimuth, distance_m * sin_vertical};
}

}  // namespace tumble::rs16
