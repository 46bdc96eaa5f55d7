#include "daemon/scan_verdict.hpp"

namespace tumble::daemon {

ScanVerdict scan_verdict(const RegistrationRecord& r, const HealthConfig& health) {
  if (r.map_deferred) return ScanVerdict::MapDeferred;
  if (r.spin_rate_unmeasured) return ScanVerdict::SpinRateUnmeasured;
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
