// See madgwick.hpp. The gradient is Madgwick (2011) eq. 25–26 written for
// q = (w, x, y, z) = q_WI and the reference direction e_z.
#include "core/madgwick.hpp"

#include <algorithm>
#include <cmath>

#include "core/rotation.hpp"

namespace tumble {

MadgwickFilter::MadgwickFilter(const MadgwickParams& params, const Eigen::Quaterniond& q_wi, double gravity_m_s2)
    : params_(params), q_wi_(q_wi.normalized()), gravity_m_s2_(gravity_m_s2) {}

void MadgwickFilter::propagate(const Eigen::Vector3d& gyro_rad_s, double dt_s) {
  q_wi_ = integrate_body_rate(q_wi_, gyro_rad_s, dt_s);
}

bool MadgwickFilter::update(const Eigen::Vector3d& gyro_rad_s, const Eigen::Vector3d& accel_m_s2, double dt_s) {
  propagate(gyro_rad_s, dt_s);
  const double accel_norm = accel_m_s2.norm();
  if (accel_norm == 0.0 || std::abs(accel_norm - gravity_m_s2_) > params_.accel_gate_m_s2) return false;
  const Eigen::Vector3d a = accel_m_s2 / accel_norm;

  const double w = q_wi_.w(), x = q_wi_.x(), y = q_wi_.y(), z = q_wi_.z();
  // f = R(q)ᵀ e_z − a: the predicted "up" in the IMU frame minus the measured one.
  const Eigen::Vector3d f(2.0 * (x * z - w * y) - a.x(), 2.0 * (y * z + w * x) - a.y(),
                          1.0 - 2.0 * (x * x + y * y) - a.z());
  Eigen::Matrix<double, 3, 4> jacobian;  // ∂f/∂(w, x, y, z)
  jacobian << -2.0 * y, 2.0 * z, -2.0 * w, 2.0 * x,  //
      2.0 * x, 2.0 * w, 2.0 * z, 2.0 * y,            //
      0.0, -4.0 * x, -4.0 * y, 0.0;
  const Eigen::Vector4d gradient = jacobian.transpose() * f;
  const double gradient_norm = gradient.norm();
  // Already aligned to rounding: normalising a gradient of pure rounding noise
  // would take a full β·dt step in an arbitrary direction.
  if (gradient_norm < 1e-12) return true;
  // A unit-quaternion step of length s turns the attitude by 2s: capping s at
  // half the tilt error stops the fixed-length step from overshooting (and
  // then chattering by β·dt around the truth) once the error is that small.
  const Eigen::Vector3d up(2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y));
  const double tilt_error_rad = std::atan2(up.cross(a).norm(), up.dot(a));
  const double step_length = std::min(params_.beta * dt_s, 0.5 * tilt_error_rad);
  const Eigen::Vector4d step = step_length * gradient / gradient_norm;
  q_wi_ = Eigen::Quaterniond(w - step[0], x - step[1], y - step[2], z - step[3]).normalized();
  return true;
}

}  // namespace tumble
