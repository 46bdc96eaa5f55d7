#include "drivers/rs16/laser_geometry.hpp"

#include <cmath>
#include <numbers>

namespace tumble::rs16 {

std::string_view to_string(AngleSource source) {
  switch (source) {
    case AngleSource::Design: return "design";
    case AngleSource::Config: return "config";
    case AngleSource::Difop: return "DIFOP";
  }
  return "unknown";
}

LaserTable make_laser_table(const std::array<double, kLasers>& vertical_deg, AngleSource source) {
  LaserTable t;
  t.source = source;
  t.vertical_deg = vertical_deg;
  for (int i = 0; i < kLasers; ++i) {
    const double rad = vertical_deg[i] * std::numbers::pi / 180.0;
    t.cos_vertical[i] = std::cos(rad);
    t.sin_vertical[i] = std::sin(rad);
  }
  return t;
}

}  // namespace tumble::rs16
