#include "tools/sim/motion_rolling_cage.hpp"

#include "tools/sim/motion_primitives.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace tumble::sim {

namespace {

// Moments of the take-off impact for a unit duration: acceleration blends
// 0 -> peak -> -g over two halves. m0 = velocity gained, m1 = height gained.
struct ImpactMoments {
  double m0, m1;
};

ImpactMoments takeoff_moments(double peak_accel_m_s2) {
  ScalarProfile unit;
  unit.blend_accel_to(peak_accel_m_s2, 0.5);
  unit.blend_accel_to(-kStandardGravity_m_s2, 0.5);
  const ProfileSample e = unit.end_state();
  return {e.v, e.s};
}

// Launch speed that makes the centre's apex `height_m` above R. The landing
// impact is the time-reverse of the take-off (-g -> peak -> 0), so by symmetry
// it lands at the same speed, takes as long, and brings the centre back to R
// exactly at rest: the height gained during the impact, m1 * tau^2, plus the
// ballistic rise v^2 / 2g is the apex.
double launch_speed_m_s(double height_m, double peak_accel_m_s2) {
  const ImpactMoments m = takeoff_moments(peak_accel_m_s2);
  return std::sqrt(height_m / (m.m1 / (m.m0 * m.m0) + 1.0 / (2.0 * kStandardGravity_m_s2)));
}

// Deterministic uniform in [lo, hi] on any standard library (the std
// distributions are implementation-defined; mt19937_64 itself is not).
double uniform(std::mt19937_64& rng, double lo, double hi) {
  const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return lo + (hi - lo) * u;
}

struct Interval {
  double begin, end;
};

// Constant nonzero-rate parts of the base roll, merged where they touch.
std::vector<Interval> constant_rate_intervals(const ScalarProfile& roll) {
  std::vector<Interval> out;
  for (const auto& seg : roll.segments()) {
    if (seg.c0 != 0.0 || seg.c1 != 0.0 || seg.v0 == 0.0) continue;
    if (!out.empty() && out.back().end == seg.t0) {
      out.back().end = seg.t0 + seg.duration;
    } else {
      out.push_back({seg.t0, seg.t0 + seg.duration});
    }
  }
  return out;
}

// Removes [t, t + length] plus `gap` on both sides from the free intervals and
// returns t, drawn uniformly over all admissible starts.
double take_slot(std::vector<Interval>& free, double length, double gap, std::mt19937_64& rng, const char* key) {
  double total = 0;
  for (const auto& f : free) total += std::max(0.0, f.end - f.begin - length);
  if (!(total > 0))
    throw CageEventsDoNotFit(key, "too many events: they do not fit, with min_gap_s between them, in the parts of the roll at a constant nonzero rate");
  double u = uniform(rng, 0.0, total);
  std::size_t chosen = 0;
  double offset = 0;
  for (std::size_t i = 0; i < free.size(); ++i) {
    const double room = std::max(0.0, free[i].end - free[i].begin - length);
    if (room <= 0) continue;
    chosen = i;
    offset = std::min(u, room);
    if (u <= room) break;
    u -= room;
  }
  const Interval slot = free[chosen];
  const double t = slot.begin + offset;
  free.erase(free.begin() + static_cast<std::ptrdiff_t>(chosen));
  const Interval after{t + length + gap, slot.end};
  const Interval before{slot.begin, t - gap};
  if (after.end > after.begin) free.insert(free.begin() + static_cast<std::ptrdiff_t>(chosen), after);
  if (before.end > before.begin) free.insert(free.begin() + static_cast<std::ptrdiff_t>(chosen), before);
  return t;
}

}  // namespace

ScalarProfile bounce_profile(double t_start_s, double height_m, double peak_accel_m_s2) {
  const ImpactMoments m = takeoff_moments(peak_accel_m_s2);
  const double v_up = launch_speed_m_s(height_m, peak_accel_m_s2);
  const double impact_s = v_up / m.m0;
  ScalarProfile p(0, 0, t_start_s);
  p.blend_accel_to(peak_accel_m_s2, impact_s / 2);
  p.blend_accel_to(-kStandardGravity_m_s2, impact_s / 2);
  p.hold(2.0 * v_up / kStandardGravity_m_s2);
  p.blend_accel_to(peak_accel_m_s2, impact_s / 2);
  p.blend_accel_to(0.0, impact_s / 2);
  return p;
}

double bounce_duration_s(double height_m, double peak_accel_m_s2) {
  const double v_up = launch_speed_m_s(height_m, peak_accel_m_s2);
  return 2.0 * v_up / takeoff_moments(peak_accel_m_s2).m0 + 2.0 * v_up / kStandardGravity_m_s2;
}

double jolt_duration_s(double peak_accel_rad_s2, double rate_swing_rad_s) {
  return 4.0 * std::abs(rate_swing_rad_s / peak_accel_rad_s2);
}

void place_cage_events(RollingCageParams& params, const CageEventRanges& r, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Interval> free = constant_rate_intervals(params.roll_rad);
  for (int i = 0; i < r.bounce_count; ++i) {
    CageBounce b;
    b.height_m = uniform(rng, r.bounce_height_min_m, r.bounce_height_max_m);
    b.peak_accel_m_s2 = uniform(rng, r.bounce_peak_min_m_s2, r.bounce_peak_max_m_s2);
    b.t_start_s = take_slot(free, bounce_duration_s(b.height_m, b.peak_accel_m_s2), r.min_gap_s, rng, "bounces.count");
    params.bounces.push_back(b);
  }
  for (int i = 0; i < r.jolt_count; ++i) {
    CageJolt j;
    j.rate_swing_rad_s = uniform(rng, r.jolt_swing_min_rad_s, r.jolt_swing_max_rad_s);
    const double sign = (rng() & 1U) ? 1.0 : -1.0;
    j.peak_accel_rad_s2 = sign * uniform(rng, r.jolt_peak_min_rad_s2, r.jolt_peak_max_rad_s2);
    j.t_start_s = take_slot(free, jolt_duration_s(j.peak_accel_rad_s2, j.rate_swing_rad_s), r.min_gap_s, rng, "jolts.count");
    params.jolts.push_back(j);
  }
}

RollingCageMotion::RollingCageMotion(RollingCageParams params)
    : radius_m_(params.radius_m), roll_rad_(std::move(params.roll_rad)), mount_(at_rest(params.mount)) {
  if (!(radius_m_ > 0)) throw std::invalid_argument("the cage radius must be positive");
  std::vector<Interval> busy;
  for (const CageBounce& b : params.bounces) {
    if (!(b.height_m > 0) || !(b.peak_accel_m_s2 > kStandardGravity_m_s2))
      throw std::invalid_argument("a bounce needs a height > 0 and a peak acceleration > g");
    bounce_heights_.push_back(bounce_profile(b.t_start_s, b.height_m, b.peak_accel_m_s2));
    busy.push_back({b.t_start_s, bounce_heights_.back().end_s()});
  }
  for (const CageJolt& j : params.jolts) {
    if (j.peak_accel_rad_s2 == 0.0 || !(j.rate_swing_rad_s > 0))
      throw std::invalid_argument("a jolt needs a nonzero peak and a rate swing > 0");
    ScalarProfile p(0, 0, j.t_start_s);
    p.jolt(j.peak_accel_rad_s2, jolt_duration_s(j.peak_accel_rad_s2, j.rate_swing_rad_s));
    busy.push_back({j.t_start_s, p.end_s()});
    jolt_angles_.push_back(std::move(p));
  }
  std::sort(busy.begin(), busy.end(), [](const Interval& a, const Interval& b) { return a.begin < b.begin; });
  for (std::size_t i = 1; i < busy.size(); ++i)
    if (busy[i].begin < busy[i - 1].end)
      throw std::invalid_argument("cage events overlap at t = " + std::to_string(busy[i].begin) + " s");
  duration_s_ = roll_rad_.end_s();
}

MotionState RollingCageMotion::cage_at(double t_s) const {
  const double t = std::clamp(t_s, 0.0, duration_s_);
  ProfileSample roll = roll_rad_.at(t);
  for (const ScalarProfile& j : jolt_angles_) {
    const ProfileSample s = j.at(t);
    roll.s += s.s;
    roll.v += s.v;
    roll.a += s.a;
  }
  ProfileSample lift;
  for (const ScalarProfile& b : bounce_heights_) {
    const ProfileSample s = b.at(t);
    lift.s += s.s;
    lift.v += s.v;
    lift.a += s.a;
  }
  // Rolling about +y moves the centre along +x by R per radian. The centre
  // translates without rotating and the cage turns about a fixed axis, so
  // their composition is just both side by side.
  MotionState cage = rotation_state(Eigen::Vector3d::UnitY(), roll);
  cage.T_wb.translation() = Eigen::Vector3d(radius_m_ * roll.s, 0, radius_m_ + lift.s);
  cage.v_w = Eigen::Vector3d(radius_m_ * roll.v, 0, lift.v);
  cage.a_w = Eigen::Vector3d(radius_m_ * roll.a, 0, lift.a);
  return cage;
}

MotionState RollingCageMotion::at(double t_s) const { return compose(cage_at(t_s), mount_); }

bool RollingCageMotion::in_bounce(double t_s) const {
  for (const ScalarProfile& b : bounce_heights_)
    if (t_s >= b.start_s() && t_s <= b.end_s()) return true;
  return false;
}

}  // namespace tumble::sim
