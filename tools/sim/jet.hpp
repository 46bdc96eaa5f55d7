// A value with its first two time derivatives, for building exact motion
// signals from products of simple functions.
#pragma once

#include "tools/sim/scalar_profile.hpp"

#include <cmath>

namespace tumble::sim {

struct Jet {
  double v = 0, d = 0, dd = 0;
};

inline Jet operator*(const Jet& a, const Jet& b) {
  return {a.v * b.v, a.d * b.v + a.v * b.d, a.dd * b.v + 2.0 * a.d * b.d + a.v * b.dd};
}

inline Jet operator+(const Jet& a, const Jet& b) { return {a.v + b.v, a.d + b.d, a.dd + b.dd}; }

// amplitude * sin(omega t + phase)
inline Jet sinusoid(double amplitude, double omega_rad_s, double phase_rad, double t_s) {
  const double s = std::sin(omega_rad_s * t_s + phase_rad), c = std::cos(omega_rad_s * t_s + phase_rad);
  return {amplitude * s, amplitude * omega_rad_s * c, -amplitude * omega_rad_s * omega_rad_s * s};
}

inline ProfileSample to_sample(const Jet& j) { return {j.v, j.d, j.dd, 0.0}; }

}  // namespace tumble::sim
