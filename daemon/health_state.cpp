#include "daemon/health_state.hpp"

namespace tumble::daemon {

std::string_view to_string(HealthState state) {
  switch (state) {
    case HealthState::WaitingForSensors:
      return "waiting_for_sensors";
    case HealthState::Initialising:
      return "initialising";
    case HealthState::Tracking:
      return "tracking";
    case HealthState::Degraded:
      return "degraded";
    case HealthState::Lost:
      return "lost";
  }
  return "unknown";
}

namespace {

constexpr std::string_view kLidarSilent = "no lidar data for too long: the pose is the IMU's alone";
constexpr std::string_view kSpinRateUnmeasured =
    "gyro clipped about the lidar's spin axis: the spin is new, or the scan matched too little of the map to carry "
    "that rotation";

constexpr std::string_view kMapDeferred =
    "no local map yet: the gyro is clipped, and the first map starts only from a scan it measured whole";

constexpr std::string_view kWeaklyConstrained =
    "registration weakly constrained: expected position error above daemon.health.max_expected_error_m";

constexpr std::string_view kDirectionUnobserved =
    "direction unobserved: most recent scans leave one direction unpinned (a corridor's axis?); "
    "the pose along it is not measured";

constexpr std::string_view kImuBridged =
    "registered without IMU data: de-skewed and predicted from the registrations alone";

constexpr std::string_view kJumped =
    "registration jumped from the IMU's prediction (registration.jump_sigmas): the prediction or the scan is wrong";

constexpr std::string_view kAwaitingRest =
    "tracking lost: waiting for the robot to be still to start again from zero velocity";

constexpr std::string_view kVelocityUnconfirmed =
    "velocity unconfirmed since the IMU gap: the registrations alone measured it; good again once the robot rests";

std::string_view reason_of(ScanVerdict verdict) {
  switch (verdict) {
    case ScanVerdict::Good:
      break;
    case ScanVerdict::PoorRegistration:
      return "poor scan registration";
    case ScanVerdict::WeaklyConstrained:
      return kWeaklyConstrained;
    case ScanVerdict::DirectionUnobserved:
      return kDirectionUnobserved;
    case ScanVerdict::SpinRateUnmeasured:
      return kSpinRateUnmeasured;
    case ScanVerdict::MapDeferred:
      return kMapDeferred;
    case ScanVerdict::ImuBridged:
      return kImuBridged;
    case ScanVerdict::Jumped:
      return kJumped;
    case ScanVerdict::AwaitingRest:
      return kAwaitingRest;
    case ScanVerdict::VelocityUnconfirmed:
      return kVelocityUnconfirmed;
  }
  return {};
}

// Ignored, but a restart without lidar.source_ip may lock onto it, and a
// host that sends at a lidar's rate may be spoofing the lidar's address too.
constexpr std::string_view kSecondLidar =
    "a second host sends lidar traffic at a lidar's rate: ignored, but set lidar.source_ip or find the sender";

constexpr std::string_view kNoScan =
    "no scan completed for daemon.health.scan_timeout_s: lidar points arrive but make no scan, as from a stalled motor";

std::string_view stale_sensor(const HealthInputs& in, const HealthLimits& limits) {
  if (!in.imu_fresh && !in.lidar_fresh) return "no IMU and no lidar data";
  if (!in.imu_fresh) return "no IMU data";
  if (!in.lidar_fresh) return "no lidar data";
  if (in.scan_silent_s >= limits.scan_timeout_s) return kNoScan;
  return {};
}

}  // namespace

HealthTransition next_health_state(HealthState current, double time_in_state_s, const HealthInputs& in,
                                   const HealthLimits& limits) {
  const std::string_view stale = stale_sensor(in, limits);
  const bool fresh = stale.empty();
  using S = HealthState;
  if ((current == S::Tracking || current == S::Degraded || current == S::Lost) && !in.fuser_initialised)
    return {fresh ? S::Initialising : S::WaitingForSensors, "odometry re-initialising"};
  if (in.resets_in_period > 0 && (current == S::Initialising || current == S::Tracking || current == S::Degraded))
    return {S::Lost, in.reset_reason.empty() ? std::string_view("tracking lost") : in.reset_reason};
  if ((current == S::Tracking || current == S::Degraded) && in.lidar_silent_s >= limits.lidar_silent_to_lost_s)
    return {S::Lost, kLidarSilent};
  switch (current) {
    case S::WaitingForSensors:
      if (fresh) return {S::Initialising, "IMU and lidar data arriving"};
      break;
    case S::Initialising:
      if (!fresh) return {S::WaitingForSensors, stale};
      if (in.fuser_initialised && in.consecutive_good_scans >= 1) return {S::Tracking, "first scan registered"};
      if (in.worst_scan_in_period == ScanVerdict::MapDeferred) return {S::Initialising, kMapDeferred};
      break;
    case S::Tracking:
      if (!fresh) return {S::Degraded, stale};
      if (in.worst_scan_in_period != ScanVerdict::Good) return {S::Degraded, reason_of(in.worst_scan_in_period)};
      if (in.data_dropped) return {S::Degraded, "data dropped"};
      if (in.second_lidar) return {S::Degraded, kSecondLidar};
      break;
    case S::Degraded: {
      const bool scans_good = fresh && !in.data_dropped && in.consecutive_good_scans >= limits.good_scans_to_recover;
      if (scans_good && !in.second_lidar) return {S::Tracking, "registration good again"};
      // The pose is the lidar's and good: the second sender alone keeps it degraded, never lost.
      if (scans_good) return {S::Degraded, kSecondLidar, true};
      if (time_in_state_s >= limits.degraded_to_lost_s) return {S::Lost, "degraded for too long"};
      if (!fresh) return {S::Degraded, stale};  // still degraded, and a sensor is why: say so
      if (in.second_lidar) return {S::Degraded, kSecondLidar};
      // A specific reason is restated; a poor registration is what degraded means.
      if (in.worst_scan_in_period > ScanVerdict::PoorRegistration)
        return {S::Degraded, reason_of(in.worst_scan_in_period)};
      break;
    }
    case S::Lost:
      if (!fresh) break;
      if (in.new_map_since_lost) return {S::Initialising, "re-initialised: new local map"};
      // Lost already (degraded for too long), and now the map is given up too: say why.
      if (in.resets_in_period > 0 && !in.reset_reason.empty()) return {S::Lost, in.reset_reason};
      if (in.worst_scan_in_period == ScanVerdict::MapDeferred) return {S::Lost, kMapDeferred};
      if (in.worst_scan_in_period == ScanVerdict::AwaitingRest) return {S::Lost, kAwaitingRest};
      if (!in.data_dropped && in.consecutive_good_scans >= limits.good_scans_to_recover)
        return {S::Tracking, "registration good again"};
      break;
  }
  return {current, {}};
}

}  // namespace tumble::daemon
