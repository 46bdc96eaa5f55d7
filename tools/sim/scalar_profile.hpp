// A smooth 1-D motion profile s(t) (metres along a rail, radians about an
// axis) built from segments whose acceleration is c0 + c1 cos(w u) (u = time
// into the segment). Every change of acceleration is a cosine blend, so the
// acceleration is continuous everywhere and each peak is hit exactly; position,
// velocity, acceleration and jerk are closed-form.
#pragma once

#include <vector>

namespace tumble::sim {

struct ProfileSample {
  double s = 0;     // position (m or rad)
  double v = 0;     // ds/dt
  double a = 0;     // d2s/dt2
  double jerk = 0;  // d3s/dt3
};

class ScalarProfile {
 public:
  // Starts at rest at s = s0 (t = 0) unless an initial rate is given.
  explicit ScalarProfile(double s0 = 0, double v0 = 0, double t0_s = 0);

  // Building blocks (append at the end, all closed-form).
  void hold(double duration_s);                              // keep the current acceleration
  void blend_accel_to(double accel, double duration_s);      // cosine blend of acceleration to `accel`

  // Composite steps; each starts and ends with zero acceleration (precondition).
  // Velocity change with peak |acceleration| = peak_accel exactly: raised-cosine
  // rise over rise_s, plateau, cosine fall; rise_s <= 0 means a pure raised
  // cosine (no plateau). Returns false (and appends nothing) if rise_s is too long.
  bool change_velocity(double target_v, double peak_accel, double rise_s = 0);
  // Rest-to-rest move by `distance` with |v| <= max_v and |a| <= peak_accel (both
  // reached when the distance allows; max_v is lowered otherwise). Precondition: at rest.
  void travel(double distance, double max_v, double peak_accel);
  // A short impact: raised-cosine acceleration pulse of the given signed peak
  // and velocity change (same sign); duration = 2 * delta_v / peak.
  void shock(double peak_accel, double delta_v);
  // Zero-net-velocity jolt: +peak then -peak (sign of peak first), four cosine
  // quarters of duration_s / 4; the rate swings by peak * duration_s / 4 and returns.
  void jolt(double peak_accel, double duration_s);

  ProfileSample at(double t_s) const;  // clamped to [t0, end]: before/after, the end state extrapolates at constant velocity
  double start_s() const { return t0_s_; }
  double end_s() const;
  const ProfileSample& end_state() const { return end_; }  // state at end_s()
  double max_abs_velocity() const;     // over the whole profile (exact per segment)
  double max_abs_accel() const;        // idem
  bool empty() const { return segments_.empty(); }

  struct Segment {
    double t0 = 0, duration = 0;
    double s0 = 0, v0 = 0;
    double c0 = 0, c1 = 0, w = 0;  // a(u) = c0 + c1 cos(w u)
  };
  const std::vector<Segment>& segments() const { return segments_; }

 private:
  void append(double duration_s, double c0, double c1, double w);

  double t0_s_;
  ProfileSample start_;
  ProfileSample end_;     // cached: events extrapolate from it at every query after they end
  double end_accel_ = 0;  // the nominal acceleration at the end (exact, unlike cos(w * duration))
  std::vector<Segment> segments_;
};

// Evaluates one segment at time u into it (exposed for tests).
ProfileSample evaluate_segment(const ScalarProfile::Segment& seg, double u);

}  // namespace tumble::sim
