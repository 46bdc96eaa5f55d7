#include "tools/sim/motion_walk.hpp"

#include "tools/sim/jet.hpp"
#include "tools/sim/motion_primitives.hpp"

#include <algorithm>
#include <numbers>

namespace tumble::sim {

namespace {

// Rz(yaw) Ry(pitch) Rx(roll), each an exact fixed-axis rotation state.
MotionState ypr_state(const Jet& yaw, const Jet& pitch, const Jet& roll) {
  return compose(rotation_state(Eigen::Vector3d::UnitZ(), to_sample(yaw)),
                 compose(rotation_state(Eigen::Vector3d::UnitY(), to_sample(pitch)),
                         rotation_state(Eigen::Vector3d::UnitX(), to_sample(roll))));
}

MotionState position_state(const Jet& x, const Jet& y, const Jet& z) {
  MotionState s;
  s.T_wb.translation() = Eigen::Vector3d(x.v, y.v, z.v);
  s.v_w = Eigen::Vector3d(x.d, y.d, z.d);
  s.a_w = Eigen::Vector3d(x.dd, y.dd, z.dd);
  return s;
}

}  // namespace

WalkMotion::WalkMotion(WalkParams params) : params_(std::move(params)), mount_(at_rest(params_.mount)) {
  const double v_max = params_.forward_m.max_abs_velocity();
  speed_scale_ = v_max > 0 ? 1.0 / v_max : 0.0;
}

MotionState WalkMotion::at(double t_s) const {
  const double t = std::clamp(t_s, 0.0, duration_s());
  const ProfileSample f = params_.forward_m.at(t);
  // Gait amplitude follows the walking speed, so it fades in and out with it.
  const Jet gait{std::abs(f.v) * speed_scale_, (f.v < 0 ? -f.a : f.a) * speed_scale_,
                 (f.v < 0 ? -f.jerk : f.jerk) * speed_scale_};
  const double step_w = 2.0 * std::numbers::pi * params_.step_frequency_hz;
  const double cycle_w = 0.5 * step_w;
  const WalkParams& p = params_;
  const Jet forward{f.s, f.v, f.a};
  const Jet sway = gait * sinusoid(p.sway_m, cycle_w, 0.0, t);
  const Jet bob = gait * sinusoid(p.bob_m, step_w, 0.0, t);
  // Yaw and roll swing with the lateral sway; pitch nods with each step.
  const Jet yaw = gait * sinusoid(p.yaw_sway_rad, cycle_w, 0.5 * std::numbers::pi, t);
  const Jet pitch = gait * sinusoid(p.pitch_bob_rad, step_w, 0.5 * std::numbers::pi, t);
  const Jet roll = gait * sinusoid(p.roll_sway_rad, cycle_w, 0.0, t);
  return compose(compose(position_state(forward, sway, bob), ypr_state(yaw, pitch, roll)), mount_);
}

namespace {

// Cycloidal fade in over [0, fade] and out over [duration - fade, duration]:
// e(s) = s - sin(2 pi s) / (2 pi) has zero first and second derivatives at
// both ends, so the shake starts and stops with continuous acceleration.
Jet fade_envelope(double t, double duration, double fade) {
  if (fade <= 0) return {1, 0, 0};
  double sign = 1;
  double u = t;
  if (t > duration - fade) {
    u = duration - t;
    sign = -1;  // d/dt of e(duration - t) = -e'
  }
  if (u >= fade) return {1, 0, 0};
  const double s = std::max(u, 0.0) / fade;
  const double two_pi = 2.0 * std::numbers::pi;
  return {s - std::sin(two_pi * s) / two_pi, sign * (1.0 - std::cos(two_pi * s)) / fade,
          two_pi * std::sin(two_pi * s) / (fade * fade)};
}

}  // namespace

MotionState VibrationMotion::at(double t_s) const {
  const VibrationParams& p = params_;
  const double t = std::clamp(t_s, 0.0, p.duration_s);
  const Jet env = fade_envelope(t, p.duration_s, p.fade_s);
  const double w = 2.0 * std::numbers::pi * p.frequency_hz;
  // Axes a third of a period apart, so the shake is not along one line.
  Jet tr[3], rot[3];
  for (int i = 0; i < 3; ++i) {
    const double phase = 2.0 * std::numbers::pi * i / 3.0;
    tr[i] = env * sinusoid(p.translation_m[i], w, phase, t);
    rot[i] = env * sinusoid(p.rotation_rad[i], w, phase, t);
  }
  return compose(position_state(tr[0], tr[1], tr[2]), ypr_state(rot[2], rot[1], rot[0]));
}

}  // namespace tumble::sim
