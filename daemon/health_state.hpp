// tumbled's health state machine, evaluated once per status period.
//
//   WAITING_FOR_SENSORS --both sensors fresh--> INITIALISING
//   INITIALISING --a sensor stale--> WAITING_FOR_SENSORS
//   INITIALISING --fuser initialised and a good scan registered--> TRACKING
//   TRACKING --a sensor stale, a bad scan, data dropped, or a second lidar
//              on the network--> DEGRADED
//   DEGRADED --sensors fresh, nothing dropped, no second lidar,
//              good_scans_to_recover consecutive good scans--> TRACKING
//   DEGRADED --degraded for degraded_to_lost_s--> LOST
//   TRACKING, DEGRADED --no lidar data for lidar_silent_to_lost_s--> LOST
//              (the registration starts a new local map on the next scan)
//   INITIALISING, TRACKING, DEGRADED --the registration gave up its local map
//              (a reset, with its reason)--> LOST
//   LOST --sensors fresh and a new local map started since--> INITIALISING
//              (after a loss of track the new map waits for the robot to
//              rest: the fuser starts again from zero velocity there, and
//              the state stays LOST, saying so, until then)
//   LOST --sensors fresh, nothing dropped, good_scans_to_recover
//              consecutive good scans (the map was kept)--> TRACKING
//   TRACKING, DEGRADED, LOST --fuser no longer initialised--> INITIALISING
//              (or WAITING_FOR_SENSORS if a sensor is stale)
//
// LOST is never terminal: the registration thread re-initialises by itself
// (a new local map continuing the last pose, core_stages.hpp), and a map that
// was kept can be tracked against again.
// "Fresh": data arrived within daemon.health.sensor_timeout_s: a valid IMU
// sample, a lidar datagram that gave points. Lidar points that complete no
// scan for scan_timeout_s (a stalled motor with its lasers firing) are a
// stale lidar too, with their own reason: degraded, then lost after
// degraded_to_lost_s (the first scan after a gap of lidar_silent_to_lost_s
// starts a new local map, a reset). "Good scan":
// registered and used (not untrusted), converged, matched ratio >= min_matched_ratio, degeneracy >= min_degeneracy,
// not a jump from the prediction (registration.jump_sigmas), the IMU over the scan and, since
// an IMU gap, a rest that confirmed the velocity (fuser.max_speed_at_rest_m_s),
// where the gyro was clipped about the lidar's spin axis past the spin's first spin_clipped_scans_to_settle scans
// and matched ratio >= min_matched_ratio_spin_clipped, no direction unobserved
// (core/unobserved_direction.hpp), and the expected error of the registered
// pose within daemon.health.max_expected_error_m (a bad scan for any of these
// three reasons is reported as such).
// "Data dropped": a ring dropped items or a scan was discarded in the period.
#pragma once

#include <cstdint>
#include <string_view>

namespace tumble::daemon {

// Why a scan is not good, or that it is. A period is judged by the most
// specific reason among its scans: the larger value.
enum class ScanVerdict : std::int8_t {
  Good = 0,
  PoorRegistration = 1,    // not registered, not used, not converged, too few matches or degenerate
  WeaklyConstrained = 2,   // expected error above daemon.health.max_expected_error_m
  DirectionUnobserved = 3, // a direction the recent scans have not pinned (a corridor's axis)
  SpinRateUnmeasured = 4,  // gyro clipped about the lidar's spin axis: a new spin, or matched too little
  MapDeferred = 5,         // no local map, and the gyro clipped: waiting for a scan that can start one
  ImuBridged = 6,          // registered without IMU data over the scan: its motion is the registrations' guess
  Jumped = 7,              // registered farther from the prediction than both can be wrong (registration.jump_sigmas)
  AwaitingRest = 8,        // lost: waiting for the robot to rest before a new map starts from zero velocity
  VelocityUnconfirmed = 9, // since an IMU gap the velocity is the registrations' alone, until the robot rests
};

// Values equal tumble::status_t::STATE_*.
enum class HealthState : std::int8_t { WaitingForSensors = 0, Initialising = 1, Tracking = 2, Degraded = 3, Lost = 4 };

std::string_view to_string(HealthState state);  // waiting_for_sensors, initialising, ...

struct HealthInputs {
  bool imu_fresh = false;
  bool lidar_fresh = false;
  double lidar_silent_s = 0.0;  // since the newest lidar data
  bool fuser_initialised = false;
  ScanVerdict worst_scan_in_period = ScanVerdict::Good;
  int consecutive_good_scans = 0;  // ending with the newest scan
  bool data_dropped = false;
  int resets_in_period = 0;          // local maps given up
  std::string_view reset_reason;     // of the newest of them
  bool new_map_since_lost = false;   // a scan started a new local map after the reset that lost track
  bool second_lidar = false;         // another host sends to the lidar's port at a lidar's rate
  double scan_silent_s = 0.0;        // since the newest scan completed (registered or not)
};

struct HealthLimits {
  double degraded_to_lost_s = 3.0;
  int good_scans_to_recover = 5;
  double lidar_silent_to_lost_s = 1.0;
  double scan_timeout_s = 0.5;
};

struct HealthTransition {
  HealthState state;
  std::string_view reason;  // empty when nothing changes; set when only the reason does (a stale sensor)
  // Degraded for a second lidar alone, the scans good: degraded_to_lost_s
  // measures how long the pose has been doubtful, so its clock starts again.
  bool pose_good = false;
};

// The next state, given the current one and how long it has lasted.
HealthTransition next_health_state(HealthState current, double time_in_state_s, const HealthInputs& in,
                                   const HealthLimits& limits);

}  // namespace tumble::daemon
