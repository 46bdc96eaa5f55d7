// A registration record that every test of scan_verdict() calls good under
// the default HealthConfig: what the daemon's tests start from and vary one
// field of.
#pragma once

#include "daemon/records.hpp"

namespace tumble::daemon {

inline RegistrationRecord good_registration() {
  RegistrationRecord r;
  r.registered = true;
  r.converged = true;
  r.inlier_ratio = 0.6f;
  r.matched_ratio = 0.6f;
  r.degeneracy = 0.5f;
  return r;
}

}  // namespace tumble::daemon
