#include "daemon/scan_verdict.hpp"

#include <gtest/gtest.h>

#include "test/daemon/good_registration.hpp"

namespace tumble::daemon {
namespace {

TEST(ScanVerdict, AWeaklyPinnedDirectionIsPoorOnlyWithoutThePredictionAsPrior) {
  const HealthConfig health;
  RegistrationRecord r = good_registration();
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::Good);
  r.degeneracy = 0.0007f;  // over daemon.health.min_degeneracy (0.0005): a rotation this weak still turns right
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::Good);
  r.degeneracy = 0.0004f;  // under it
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

TEST(ScanVerdict, AJumpAScanWithoutTheImuAndAWaitForRestAreNeverGood) {
  const HealthConfig health;
  RegistrationRecord r = good_registration();
  r.imu_bridged = true;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::ImuBridged);
  r.jumped = true;  // the more specific
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::Jumped);
  r = good_registration();
  r.registered = false;
  r.awaiting_rest = true;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::AwaitingRest);
}

TEST(ScanVerdict, AScanAfterAnImuGapIsNotGoodUntilARestConfirmsTheVelocity) {
  const HealthConfig health;
  RegistrationRecord r = good_registration();
  r.velocity_unconfirmed = true;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::VelocityUnconfirmed);
  r.velocity_unconfirmed = false;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::Good);
}

TEST(ScanVerdict, AClippedSpinIsGoodOnlyOnceSettledAndWhereTheScanMatchedMoreThanAMeasuredOneMust) {
  const HealthConfig health;
  RegistrationRecord r = good_registration();
  r.matched_ratio = 0.27f;  // between min_matched_ratio (0.25) and min_matched_ratio_spin_clipped (0.3)
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::Good);
  r.spin_rate_unmeasured = true;
  r.spin_clipped_scans_in_row = 4;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::SpinRateUnmeasured);
  r.matched_ratio = 0.35f;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::Good);
  // The spin's first scans (spin_clipped_scans_to_settle, 3): the fuser's rate still lags it.
  for (std::int32_t n = 1; n <= 3; ++n) {
    r.spin_clipped_scans_in_row = n;
    EXPECT_EQ(scan_verdict(r, health), ScanVerdict::SpinRateUnmeasured) << n;
  }
  r.spin_clipped_scans_in_row = 4;
  // The other tests still apply to a settled clipped scan that matched well.
  r.expected_error_m = 0.05f;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::WeaklyConstrained);
  r.expected_error_m = 0.01f;
  r.degeneracy = 0.0004f;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::PoorRegistration);
  // Not registered: the rotation is nobody's.
  r = good_registration();
  r.spin_rate_unmeasured = true;
  r.spin_clipped_scans_in_row = 4;
  r.registered = false;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::SpinRateUnmeasured);
  r.spin_rate_unmeasured = false;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::PoorRegistration);
  r = good_registration();
  r.matched_ratio = 0.2f;
  EXPECT_EQ(scan_verdict(r, health), ScanVerdict::PoorRegistration);
}

}  // namespace
}  // namespace tumble::daemon
