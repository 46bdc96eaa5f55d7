// Madgwick attitude filter, IMU variant (gyro + accelerometer, no
// magnetometer), as the paper's fuser uses it (§III-B, docs/method.md §1).
//
//   q̇ = ½ q ⊗ (0, ω) − β ∇f/‖∇f‖,   f(q) = R(q)ᵀ e_z − a/‖a‖
//
// q = q_WI rotates IMU-frame vectors into the gravity-aligned world W (z up);
// at rest the accelerometer measures +g along W's z. Yaw is unobservable and
// only integrated.
//
// Discretisation (our choice): the gyro part is integrated exactly,
// q ⊗ Exp(ω dt), so a constant rate is tracked without the first-order error
// of Madgwick's q += q̇ dt (0.11 rad per step at 11 rad/s and 100 Hz); the
// gradient step is then taken at the predicted attitude, and is no longer
// than the tilt error (ours): the normalised step has a fixed length β·dt, so
// uncapped it overshoots a smaller error and chatters by β·dt around it.
//
// Accelerometer gate (ours): during shocks (the rail's 200 m/s² peaks) the
// accelerometer does not measure gravity, so the correction is skipped when
// | ‖a‖ − g | > accel_gate.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tumble {

struct MadgwickParams {
  double beta = 0.1;              // gradient-step gain (rad/s)
  double accel_gate_m_s2 = 2.0;   // skip the correction when | ‖a‖ − g | exceeds this
};

class MadgwickFilter {
 public:
  // gravity_m_s2: the magnitude the gate compares against (the fuser passes the
  // accelerometer's own static average, so a scale error does not close the gate).
  MadgwickFilter(const MadgwickParams& params, const Eigen::Quaterniond& q_wi, double gravity_m_s2);

  // One IMU sample over dt_s. Returns true when the accelerometer correction
  // was applied (false: gated out, or zero acceleration).
  bool update(const Eigen::Vector3d& gyro_rad_s, const Eigen::Vector3d& accel_m_s2, double dt_s);
  // Gyro-only propagation, for samples whose accelerometer is known bad (clipped).
  void propagate(const Eigen::Vector3d& gyro_rad_s, double dt_s);

  const Eigen::Quaterniond& orientation() const { return q_wi_; }
  void set_orientation(const Eigen::Quaterniond& q_wi) { q_wi_ = q_wi.normalized(); }
  // Continues from an orientation this filter gave (not normalised again): a
  // step taken again after a correction must see the bits the first one saw.
  void resume_from(const Eigen::Quaterniond& q_wi) { q_wi_ = q_wi; }

 private:
  MadgwickParams params_;
  Eigen::Quaterniond q_wi_;
  double gravity_m_s2_;
};

}  // namespace tumble
