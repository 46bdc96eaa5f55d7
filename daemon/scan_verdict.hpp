// A scan judged as the health machine judges it (health_state.hpp): good, or
// the most specific reason it is not. The status aggregator feeds the health
// machine with it; the scan log writes it down, so a run's log says which of
// its scans degraded tumbled from tracking (or kept it from recovering).
#pragma once

#include "daemon/config.hpp"
#include "daemon/health_state.hpp"
#include "daemon/records.hpp"

namespace tumble::daemon {

// A registration not used (untrusted: far from the IMU-propagated pose) may
// have converged well: it is still no evidence that tracking holds. Such a
// scan is reported not registered, so it is a poor registration here.
ScanVerdict scan_verdict(const RegistrationRecord& r, const HealthConfig& health);

}  // namespace tumble::daemon
