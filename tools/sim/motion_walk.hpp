// A person walking with a handheld sensor along the carrier x axis: forward
// distance from a smooth profile, plus gait bob (vertical, at the step
// frequency), lateral sway, and yaw/pitch/roll oscillations. The gait
// amplitudes scale with the walking speed (speed / max speed), so they fade in
// and out with it and the motion starts and ends at rest.
#pragma once

#include "tools/sim/motion.hpp"
#include "tools/sim/scalar_profile.hpp"

#include <Eigen/Geometry>

namespace tumble::sim {

struct WalkParams {
  ScalarProfile forward_m;         // distance along carrier x
  double step_frequency_hz = 1.8;  // steps per second (two steps per gait cycle)
  double bob_m = 0.03;             // vertical amplitude, at the step frequency
  double sway_m = 0.03;            // lateral amplitude, at half the step frequency
  double yaw_sway_rad = 0.05;      // at half the step frequency
  double pitch_bob_rad = 0.02;     // at the step frequency
  double roll_sway_rad = 0.03;     // at half the step frequency
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();  // B in the hand frame
};

class WalkMotion final : public Motion {
 public:
  explicit WalkMotion(WalkParams params);
  MotionState at(double t_s) const override;
  double duration_s() const override { return params_.forward_m.end_s(); }

 private:
  WalkParams params_;
  double speed_scale_;  // 1 / max walking speed (0 if it never moves)
  MotionState mount_;
};

// Small sinusoidal shake (e.g. carriage rumble, hand tremor) of B about its
// own axes, faded in and out over fade_s (C2 cycloidal envelopes). Meant to
// be superposed on another motion (SuperposedMotion).
struct VibrationParams {
  double duration_s = 1;
  double frequency_hz = 10;
  Eigen::Vector3d translation_m = Eigen::Vector3d::Zero();  // amplitude per axis
  Eigen::Vector3d rotation_rad = Eigen::Vector3d::Zero();   // amplitude about x, y, z
  double fade_s = 0.5;
};

class VibrationMotion final : public Motion {
 public:
  explicit VibrationMotion(VibrationParams params) : params_(params) {}
  MotionState at(double t_s) const override;
  double duration_s() const override { return params_.duration_s; }

 private:
  VibrationParams params_;
};

}  // namespace tumble::sim
