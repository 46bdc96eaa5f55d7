// Small rotation helpers shared by the fuser, the trajectory and the weight
// models. Header-only: they sit on per-sample and per-point paths.
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tumble {

// q ⊗ Exp(ω dt): exact integration of a constant body rate (also used to
// extrapolate an attitude at constant rate).
inline Eigen::Quaterniond integrate_body_rate(const Eigen::Quaterniond& q, const Eigen::Vector3d& omega_rad_s,
                                              double dt_s) {
  const Eigen::Vector3d rotation = omega_rad_s * dt_s;
  const double angle = rotation.norm();
  if (angle < 1e-12) return q;
  return (q * Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation / angle))).normalized();
}

// Rodrigues rotation of p by the rotation vector `rotation` (|rotation| about
// rotation/|rotation|), with its cos/sin precomputed so that the ± pair the
// weight models need costs one sin/cos: pass sin_angle negated for −rotation.
struct AxisAngle {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  double cos_angle = 1.0;
  double sin_angle = 0.0;

  explicit AxisAngle(const Eigen::Vector3d& rotation) {
    const double angle = rotation.norm();
    if (angle > 0.0) {
      axis = rotation / angle;
      cos_angle = std::cos(angle);
      sin_angle = std::sin(angle);
    }
  }
  // Rotation by +angle (sign = +1) or −angle (sign = −1).
  Eigen::Vector3d rotate(const Eigen::Vector3d& p, double sign) const {
    return p * cos_angle + sign * sin_angle * axis.cross(p) + axis * (axis.dot(p) * (1.0 - cos_angle));
  }
};

}  // namespace tumble
