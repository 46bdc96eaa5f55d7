// The protective cage pulled by a rope (paper §IV): a cage of radius R rolls
// without slipping along the carrier x axis (rolling axis = carrier y), with
// bounces (vertical hops started and ended by short impacts) and jolts
// (short angular-acceleration impacts about the rolling axis).
//
// Guarantees: x = R * roll angle at all times (horizontal rolling relation);
// outside bounces the cage centre is at height R, so the contact point has
// zero velocity (rolling without slipping); during a bounce the centre never
// goes below R. Acceleration is continuous everywhere; every impact peak is exact.
#pragma once

#include "tools/sim/motion.hpp"
#include "tools/sim/scalar_profile.hpp"

#include <Eigen/Geometry>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace tumble::sim {

struct CageBounce {
  double t_start_s = 0;
  double height_m = 0.05;           // apex of the cage centre above R
  double peak_accel_m_s2 = 150;     // of the take-off and landing impacts (upwards), > g
};

struct CageJolt {
  double t_start_s = 0;
  double peak_accel_rad_s2 = 800;   // signed: the sign of the first half
  double rate_swing_rad_s = 1;      // > 0: the roll rate swings by this and returns
};

struct RollingCageParams {
  double radius_m = 0.25;
  ScalarProfile roll_rad;           // base roll angle (the operator's pull)
  std::vector<CageBounce> bounces;  // must not overlap each other or jolts
  std::vector<CageJolt> jolts;
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();  // B in the cage frame (origin = cage centre)
};

// Ranges for seeded random events, drawn uniformly.
struct CageEventRanges {
  int bounce_count = 0;
  double bounce_height_min_m = 0.02, bounce_height_max_m = 0.1;
  double bounce_peak_min_m_s2 = 100, bounce_peak_max_m_s2 = 200;
  int jolt_count = 0;
  double jolt_swing_min_rad_s = 0.2, jolt_swing_max_rad_s = 1;
  double jolt_peak_min_rad_s2 = 300, jolt_peak_max_rad_s2 = 800;
  double min_gap_s = 0.1;           // quiet time between any two events
};

// Thrown when the events do not fit; key is "bounces.count" or "jolts.count".
struct CageEventsDoNotFit : std::invalid_argument {
  CageEventsDoNotFit(std::string key_name, const std::string& why) : std::invalid_argument(why), key(std::move(key_name)) {}
  std::string key;
};

// Places the events at random, non-overlapping times inside the parts of the
// base roll where it rolls at a constant nonzero rate, so impacts never add
// to the pull's own acceleration. Deterministic for a seed (same result with
// any compiler). Throws CageEventsDoNotFit.
void place_cage_events(RollingCageParams& params, const CageEventRanges& ranges, std::uint64_t seed);

// Height of the cage centre above R during one bounce starting at t_start_s
// (exposed for tests): take-off impact, ballistic flight, landing impact.
ScalarProfile bounce_profile(double t_start_s, double height_m, double peak_accel_m_s2);
double bounce_duration_s(double height_m, double peak_accel_m_s2);
double jolt_duration_s(double peak_accel_rad_s2, double rate_swing_rad_s);

class RollingCageMotion final : public Motion {
 public:
  explicit RollingCageMotion(RollingCageParams params);  // throws std::invalid_argument on overlapping events
  MotionState at(double t_s) const override;
  double duration_s() const override { return duration_s_; }

  // The cage centre frame C alone (B = C * mount).
  MotionState cage_at(double t_s) const;
  double radius_m() const { return radius_m_; }
  // True when t is inside a bounce (the cage may be off the ground).
  bool in_bounce(double t_s) const;

 private:
  double radius_m_;
  ScalarProfile roll_rad_;
  std::vector<ScalarProfile> bounce_heights_;  // each starts at its bounce time
  std::vector<ScalarProfile> jolt_angles_;     // each starts at its jolt time
  MotionState mount_;
  double duration_s_ = 0;
};

}  // namespace tumble::sim
