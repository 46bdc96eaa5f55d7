// Ground-truth motion of the sensor body frame B (= lidar frame L) in the
// world W (z up, gravity (0, 0, -9.80665)). Every motion is analytic: pose and
// all derivatives are exact at any time, never integrated numerically.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>

#include "core/types.hpp"

namespace tumble::sim {

struct MotionState {                 // of the sensor cage body frame B (= lidar frame L)
  Eigen::Isometry3d T_wb = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();      // velocity of B's origin in W
  Eigen::Vector3d a_w = Eigen::Vector3d::Zero();      // acceleration of B's origin in W (no gravity)
  Eigen::Vector3d omega_b = Eigen::Vector3d::Zero();  // angular velocity of B, in B
  Eigen::Vector3d alpha_b = Eigen::Vector3d::Zero();  // angular acceleration of B, in B (= d/dt omega_b)
};

// t_s runs over [0, duration_s()]; outside it the state at the nearest end is
// returned (the shipped motions start and end at rest, so that is exact).
class Motion {
 public:
  virtual ~Motion() = default;
  virtual MotionState at(double t_s) const = 0;
  virtual double duration_s() const = 0;
};

// The state of frame C moving relative to a moving frame P: parent is P in W,
// child is C in P (child.v_w, a_w are then in P's axes). Exact rigid-body
// kinematics (Coriolis and centripetal terms included).
MotionState compose(const MotionState& parent, const MotionState& child);

// A constant pose (all rates zero).
MotionState at_rest(const Eigen::Isometry3d& T);

// Pose from position and roll-pitch-yaw in degrees: R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Isometry3d pose_from_xyz_rpy_deg(const Eigen::Vector3d& xyz_m, const Eigen::Vector3d& rpy_deg);

// A constant pose applied before a motion (W <- motion frame): T_wb(t) = origin * inner(t).
class PlacedMotion final : public Motion {
 public:
  PlacedMotion(Eigen::Isometry3d origin, std::unique_ptr<Motion> inner);
  MotionState at(double t_s) const override;
  double duration_s() const override;

 private:
  MotionState origin_;
  std::unique_ptr<Motion> inner_;
};

}  // namespace tumble::sim
