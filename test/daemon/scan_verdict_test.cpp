#include "daemon/scan_verdict.hpp"

#include <gtest/gtest.h>

namespace tumble::daemon {
namespace {

RegistrationRecord registered_scan() {
  RegistrationRecord r;
  r.registered = true;
  r.converged = true;
  r.matched_ratio = 0.8f;
  r.degeneracy = 0.01f;
  r.expected_error_m = 0.01f;
  return r;
}

TEST(ScanVerdict, AWeaklyPinnedDirectionIsPoorOnlyWithoutThePredictionAsPrior) {
  const HealthConfig health;
  RegistrationRecord r = registered_scan();
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::Good);
  r.degeneracy = 0.0005f;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::PoorRegistration);
  // The prediction was the prior, but the weak direction is a rotation: still poor.
  r.prediction_prior = true;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::PoorRegistration);
  // A weak translation the prediction carried: its expected error says how well, and judges it.
  r.weak_translation_predicted = true;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::Good);
  r.expected_error_m = 0.05f;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::WeaklyConstrained);
  // The other tests still apply.
  r.expected_error_m = 0.01f;
  r.matched_ratio = 0.1f;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::PoorRegistration);
}

}  // namespace
}  // namespace tumble::daemon
