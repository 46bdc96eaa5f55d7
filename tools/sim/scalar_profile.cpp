#include "tools/sim/scalar_profile.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

namespace tumble::sim {

ProfileSample evaluate_segment(const ScalarProfile::Segment& seg, double u) {
  ProfileSample out;
  if (seg.c1 == 0.0 || seg.w == 0.0) {
    out.a = seg.c0 + seg.c1;
    out.v = seg.v0 + out.a * u;
    out.s = seg.s0 + seg.v0 * u + 0.5 * out.a * u * u;
    return out;
  }
  const double wu = seg.w * u;
  const double sin_wu = std::sin(wu);
  const double half_sin = std::sin(0.5 * wu);
  out.a = seg.c0 + seg.c1 * std::cos(wu);
  out.jerk = -seg.c1 * seg.w * sin_wu;
  out.v = seg.v0 + seg.c0 * u + seg.c1 * sin_wu / seg.w;
  // (1 - cos wu) / w^2 written without cancellation for small wu.
  out.s = seg.s0 + seg.v0 * u + 0.5 * seg.c0 * u * u + seg.c1 * 2.0 * half_sin * half_sin / (seg.w * seg.w);
  return out;
}

ScalarProfile::ScalarProfile(double s0, double v0, double t0_s) : t0_s_(t0_s) {
  start_.s = s0;
  start_.v = v0;
  end_ = start_;
}

double ScalarProfile::end_s() const {
  return segments_.empty() ? t0_s_ : segments_.back().t0 + segments_.back().duration;
}

void ScalarProfile::append(double duration_s, double c0, double c1, double w) {
  if (!(duration_s > 0)) return;
  // Extrema are found per segment from the endpoints and one interior point,
  // which holds while the cosine covers at most half a period.
  assert(w * duration_s <= std::numbers::pi * (1 + 1e-12));
  segments_.push_back({end_s(), duration_s, end_.s, end_.v, c0, c1, w});
  end_ = evaluate_segment(segments_.back(), duration_s);
}

void ScalarProfile::hold(double duration_s) { append(duration_s, end_accel_, 0.0, 0.0); }

void ScalarProfile::blend_accel_to(double accel, double duration_s) {
  if (!(duration_s > 0)) return;
  const double a0 = end_accel_;
  append(duration_s, 0.5 * (a0 + accel), 0.5 * (a0 - accel), std::numbers::pi / duration_s);
  end_accel_ = accel;
}

bool ScalarProfile::change_velocity(double target_v, double peak_accel, double rise_s) {
  const double dv = target_v - end_state().v;
  if (dv == 0.0) return true;
  const double peak = std::copysign(std::abs(peak_accel), dv);
  if (rise_s <= 0) {
    const double half = std::abs(dv) / std::abs(peak_accel);  // raised cosine: dv = peak * duration / 2
    blend_accel_to(peak, half);
    blend_accel_to(0.0, half);
    return true;
  }
  const double plateau_s = std::abs(dv) / std::abs(peak_accel) - rise_s;  // dv = peak * (rise + plateau)
  if (plateau_s < 0) return false;
  blend_accel_to(peak, rise_s);
  hold(plateau_s);
  blend_accel_to(0.0, rise_s);
  return true;
}

void ScalarProfile::travel(double distance, double max_v, double peak_accel) {
  if (distance == 0.0) return;
  const double a = std::abs(peak_accel);
  double v = std::abs(max_v);
  // A raised-cosine ramp 0 -> v covers v^2 / a; two of them bound the cruise.
  if (2.0 * v * v / a > std::abs(distance)) v = std::sqrt(std::abs(distance) * a / 2.0);
  const double cruise_s = (std::abs(distance) - 2.0 * v * v / a) / v;
  const double sign = distance > 0 ? 1.0 : -1.0;
  change_velocity(sign * v, a);
  hold(std::max(cruise_s, 0.0));
  change_velocity(0.0, a);
}

void ScalarProfile::shock(double peak_accel, double delta_v) {
  const double half = std::abs(delta_v) / std::abs(peak_accel);
  blend_accel_to(std::copysign(std::abs(peak_accel), delta_v), half);
  blend_accel_to(0.0, half);
}

void ScalarProfile::jolt(double peak_accel, double duration_s) {
  const double q = duration_s / 4.0;
  blend_accel_to(peak_accel, q);
  blend_accel_to(0.0, q);
  blend_accel_to(-peak_accel, q);
  blend_accel_to(0.0, q);
}

ProfileSample ScalarProfile::at(double t_s) const {
  if (segments_.empty() || t_s <= t0_s_) {
    ProfileSample out = start_;
    out.s += start_.v * (t_s - t0_s_);
    return out;
  }
  const double end = end_s();
  if (t_s >= end) {
    ProfileSample out = end_state();
    out.s += out.v * (t_s - end);
    out.a = out.jerk = 0;
    return out;
  }
  auto it = std::upper_bound(segments_.begin(), segments_.end(), t_s,
                             [](double t, const Segment& s) { return t < s.t0; });
  const Segment& seg = *(it - 1);
  return evaluate_segment(seg, t_s - seg.t0);
}

double ScalarProfile::max_abs_velocity() const {
  double m = std::abs(start_.v);
  for (const Segment& seg : segments_) {
    m = std::max(m, std::abs(evaluate_segment(seg, seg.duration).v));
    // Interior extremum of v where a(u) = c0 + c1 cos(w u) = 0.
    if (seg.c1 != 0.0 && std::abs(seg.c0) <= std::abs(seg.c1)) {
      const double u = std::acos(-seg.c0 / seg.c1) / seg.w;
      if (u > 0 && u < seg.duration) m = std::max(m, std::abs(evaluate_segment(seg, u).v));
    }
  }
  return m;
}

double ScalarProfile::max_abs_accel() const {
  double m = 0;
  for (const Segment& seg : segments_)
    m = std::max({m, std::abs(evaluate_segment(seg, 0).a), std::abs(evaluate_segment(seg, seg.duration).a)});
  return m;
}

}  // namespace tumble::sim
