#include "tools/sim/motion.hpp"

#include <numbers>

namespace tumble::sim {

MotionState compose(const MotionState& parent, const MotionState& child) {
  const Eigen::Matrix3d R_p = parent.T_wb.linear();
  const Eigen::Matrix3d R_c = child.T_wb.linear();
  const Eigen::Vector3d p_c = child.T_wb.translation();
  const Eigen::Vector3d& w_p = parent.omega_b;
  const Eigen::Vector3d& al_p = parent.alpha_b;

  MotionState out;
  out.T_wb = parent.T_wb * child.T_wb;
  out.v_w = parent.v_w + R_p * (w_p.cross(p_c) + child.v_w);
  out.a_w = parent.a_w +
            R_p * (al_p.cross(p_c) + w_p.cross(w_p.cross(p_c)) + 2.0 * w_p.cross(child.v_w) + child.a_w);
  const Eigen::Vector3d w_p_in_c = R_c.transpose() * w_p;
  out.omega_b = w_p_in_c + child.omega_b;
  // d/dt (R_c^T w_p) = -w_c x (R_c^T w_p) + R_c^T alpha_p.
  out.alpha_b = R_c.transpose() * al_p - child.omega_b.cross(w_p_in_c) + child.alpha_b;
  return out;
}

MotionState at_rest(const Eigen::Isometry3d& T) {
  MotionState s;
  s.T_wb = T;
  return s;
}

Eigen::Isometry3d pose_from_xyz_rpy_deg(const Eigen::Vector3d& xyz_m, const Eigen::Vector3d& rpy_deg) {
  const Eigen::Vector3d rpy = rpy_deg * (std::numbers::pi / 180.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = xyz_m;
  return T;
}

PlacedMotion::PlacedMotion(Eigen::Isometry3d origin, std::unique_ptr<Motion> inner)
    : origin_(at_rest(origin)), inner_(std::move(inner)) {}

MotionState PlacedMotion::at(double t_s) const { return compose(origin_, inner_->at(t_s)); }

double PlacedMotion::duration_s() const { return inner_->duration_s(); }

}  // namespace tumble::sim
