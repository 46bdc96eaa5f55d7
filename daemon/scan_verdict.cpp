#include "daemon/scan_verdict.hpp"

namespace tumble::daemon {

ScanVerdict scan_verdict(const RegistrationRecord& r, const HealthConfig& health) {
  if (r.awaiting_rest) return ScanVerdict::AwaitingRest;
  if (r.map_deferred) return ScanVerdict::MapDeferred;
  // Far from a measured prediction: one of the two is wrong, and a scan
  // that agrees with the jump is no proof of which.
  if (r.jumped) return ScanVerdict::Jumped;
  // Through an IMU gap the scan's motion and the next prediction are the
  // registrations' own: a scan that agrees with them confirms nothing.
  if (r.imu_bridged) return ScanVerdict::ImuBridged;
  // After the gap, until a rest confirms the velocity the registrations
  // gave the fuser: in a scene that repeats along an axis (parked cars,
  // pillars) a scan fits as well a car's length off, and the next ones
  // follow the velocity that put it there.
  if (r.velocity_unconfirmed) return ScanVerdict::VelocityUnconfirmed;
  // With the gyro clipped about the spin axis the rotation there is the
  // registration's alone, and the fuser's rate for it is the registrations'
  // at constant velocity: wrong while the spin still rises, so a spell's
  // first scans are not good. Past that, a wrong rate smears the de-skewed
  // scan, which then finds less of the map, so a clipped scan must match
  // more than others (docs/decisions/verdict-limits.md).
  const bool spin_settled_and_matched = r.registered &&
                                        r.spin_clipped_scans_in_row > health.spin_clipped_scans_to_settle &&
                                        r.matched_ratio >= health.min_matched_ratio_spin_clipped;
  if (r.spin_rate_unmeasured && !spin_settled_and_matched) return ScanVerdict::SpinRateUnmeasured;
  if (r.direction_unobserved) return ScanVerdict::DirectionUnobserved;
  if (weakly_constrained(r, health.max_expected_error_m)) return ScanVerdict::WeaklyConstrained;
  // A weakly pinned direction is a poor registration only where nothing
  // else holds it: where it is a translation the prediction was ICP's prior
  // along, the published covariance there is the prediction's, and the
  // expected error (above) says how well it is known
  // (core/position_uncertainty.hpp). A weak rotation has no such figure.
  const bool pinned = r.degeneracy >= health.min_degeneracy || r.weak_translation_predicted;
  const bool good = r.registered && r.converged && r.matched_ratio >= health.min_matched_ratio && pinned;
  return good ? ScanVerdict::Good : ScanVerdict::PoorRegistration;
}

}  // namespace tumble::daemon
