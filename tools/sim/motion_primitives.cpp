#include "tools/sim/motion_primitives.hpp"

#include <algorithm>

namespace tumble::sim {

MotionState translation_state(const Eigen::Vector3d& axis_unit, const ProfileSample& s) {
  MotionState out;
  out.T_wb.translation() = axis_unit * s.s;
  out.v_w = axis_unit * s.v;
  out.a_w = axis_unit * s.a;
  return out;
}

MotionState rotation_state(const Eigen::Vector3d& axis_unit, const ProfileSample& angle) {
  MotionState out;
  out.T_wb.linear() = Eigen::AngleAxisd(angle.s, axis_unit).toRotationMatrix();
  // The axis is fixed by its own rotation, so it reads the same in B.
  out.omega_b = axis_unit * angle.v;
  out.alpha_b = axis_unit * angle.a;
  return out;
}

RailMotion::RailMotion(Eigen::Vector3d axis_unit, ScalarProfile position_m, Eigen::Isometry3d mount)
    : axis_(axis_unit.normalized()), position_m_(std::move(position_m)), mount_(at_rest(mount)) {}

MotionState RailMotion::at(double t_s) const {
  const double t = std::clamp(t_s, 0.0, duration_s());
  return compose(translation_state(axis_, position_m_.at(t)), mount_);
}

TurntableMotion::TurntableMotion(Eigen::Vector3d axis_unit, ScalarProfile angle_rad, Eigen::Isometry3d mount)
    : axis_(axis_unit.normalized()), angle_rad_(std::move(angle_rad)), mount_(at_rest(mount)) {}

MotionState TurntableMotion::at(double t_s) const {
  const double t = std::clamp(t_s, 0.0, duration_s());
  return compose(rotation_state(axis_, angle_rad_.at(t)), mount_);
}

}  // namespace tumble::sim
