// The simple carriers of the bench: standing still, the linear rail and the
// turntable. Each moves a carrier frame; B sits on it at a fixed `mount`.
#pragma once

#include "tools/sim/motion.hpp"
#include "tools/sim/scalar_profile.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tumble::sim {

class StaticMotion final : public Motion {
 public:
  explicit StaticMotion(double duration_s) : duration_s_(duration_s) {}
  MotionState at(double) const override { return {}; }
  double duration_s() const override { return duration_s_; }

 private:
  double duration_s_;
};

// Carriage translating along a fixed unit axis: carrier = translate(axis * s(t)).
class RailMotion final : public Motion {
 public:
  RailMotion(Eigen::Vector3d axis_unit, ScalarProfile position_m, Eigen::Isometry3d mount = Eigen::Isometry3d::Identity());
  MotionState at(double t_s) const override;
  double duration_s() const override { return position_m_.end_s(); }
  const ScalarProfile& profile() const { return position_m_; }

 private:
  Eigen::Vector3d axis_;
  ScalarProfile position_m_;
  MotionState mount_;
};

// Table spinning about a fixed unit axis through the motion frame's origin:
// carrier = rotation(axis, angle(t)); B at `mount` on the table (off-axis
// mounts see centripetal and tangential acceleration).
class TurntableMotion final : public Motion {
 public:
  TurntableMotion(Eigen::Vector3d axis_unit, ScalarProfile angle_rad, Eigen::Isometry3d mount = Eigen::Isometry3d::Identity());
  MotionState at(double t_s) const override;
  double duration_s() const override { return angle_rad_.end_s(); }
  const ScalarProfile& profile() const { return angle_rad_; }

 private:
  Eigen::Vector3d axis_;
  ScalarProfile angle_rad_;
  MotionState mount_;
};

// Building blocks shared by the motions (exact, from a profile sample).
MotionState translation_state(const Eigen::Vector3d& axis_unit, const ProfileSample& s);
MotionState rotation_state(const Eigen::Vector3d& axis_unit, const ProfileSample& angle);

}  // namespace tumble::sim
