#include "daemon/scan_verdict.hpp"

namespace tumble::daemon {

ScanVerdict scan_verdict(const RegistrationRecord& r, const HealthConfig& health) {
  if (r.map_deferred) return ScanVerdict::MapDeferred;
  if (r.spin_rate_unmeasured) return ScanVerdict::SpinRateUnmeasured;
  if (r.direction_unobserved) return ScanVerdict::DirectionUnobserved;
  if (weakly_constrained(r, health.max_expected_error_m)) return ScanVerdict::WeaklyConstrained;
  const bool good = r.registered && r.converged && r.matched_ratio >= health.min_matched_ratio &&
                    r.degeneracy >= health.min_degeneracy;
  return good ? ScanVerdict::Good : ScanVerdict::PoorRegistration;
}

}  // namespace tumble::daemon
