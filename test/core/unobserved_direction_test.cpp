#include "core/unobserved_direction.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace tumble {
namespace {

Degeneracy weakest(double min_eigenvalue, const Vector6d& direction = Vector6d::Unit(0), double length_scale_m = 1.0) {
  Degeneracy d;
  d.min_eigenvalue = min_eigenvalue;
  d.direction = direction;
  d.length_scale_m = length_scale_m;
  return d;
}

UnobservedDirectionParams params() {
  UnobservedDirectionParams p;
  p.weak_min_eigenvalue = 0.002;
  p.window_scans = 10;
  p.enter_fraction = 0.9;
  p.sigma_m = 2.0;
  return p;
}

TEST(UnobservedDirection, SaysWhichScanEndedASpell) {
  UnobservedDirection tracker(params());
  const Degeneracy weak = weakest(0.001), strong = weakest(0.01);
  for (int i = 0; i < 9; ++i) tracker.add(weak);
  ASSERT_TRUE(tracker.add(weak));
  EXPECT_FALSE(tracker.spell_ended());
  // 10 in the window: the spell ends once fewer than 4.5 are weak, at the 6th strong scan.
  for (int i = 1; i <= 6; ++i) {
    tracker.add(strong);
    EXPECT_EQ(tracker.spell_ended(), i == 6) << i;
  }
  EXPECT_FALSE(tracker.add(strong));
  EXPECT_FALSE(tracker.spell_ended());  // once only
}

TEST(UnobservedDirection, ASpellLastsUntilTheWindowHoldsNoWeakScan) {
  UnobservedDirection tracker(params());
  const Degeneracy weak = weakest(0.001), strong = weakest(0.01);
  for (int i = 0; i < 8; ++i) tracker.add(weak);
  EXPECT_FALSE(tracker.since_spell());  // 8 of 10 weak: no spell yet
  tracker.add(weak);
  ASSERT_TRUE(tracker.add(weak));
  EXPECT_TRUE(tracker.since_spell());
  // The spell ends at the 6th strong scan; the weak scans left in the window
  // keep since_spell until the 10th.
  for (int i = 1; i <= 10; ++i) {
    tracker.add(strong);
    EXPECT_EQ(tracker.since_spell(), i < 10) << i;
  }
  // A weak scan now is one weak scan, not a spell.
  tracker.add(weak);
  EXPECT_FALSE(tracker.since_spell());
}

TEST(UnobservedDirection, AFullWindowAtTheBarMarksItAndFewerThanHalfTheBarClearsIt) {
  UnobservedDirection tracker(params());
  const Degeneracy weak = weakest(0.001), strong = weakest(0.01);
  for (int i = 0; i < 9; ++i) EXPECT_FALSE(tracker.add(weak)) << i;  // the window is not full yet
  EXPECT_TRUE(tracker.add(weak));
  // Strong scans inside the period are marked too (one scan is not the
  // direction seen again) down to 5 weak of 10; the 6th leaves 4: 0.4 < 0.45.
  int strong_until_clear = 0;
  while (tracker.add(strong)) ++strong_until_clear;
  EXPECT_EQ(strong_until_clear, 5);
  // Between the bars it stays clear: the window must hold 9 weak of 10 again
  // (the first 4 weak scans replace the oldest, which were weak too).
  for (int i = 0; i < 8; ++i) EXPECT_FALSE(tracker.add(weak)) << i;
  EXPECT_TRUE(tracker.add(weak));
}

TEST(UnobservedDirection, WeakScansAmongStrongOnesNeverMarkIt) {
  // A rolling cage that looks at the floor one scan in two.
  UnobservedDirection tracker(params());
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(tracker.add(weakest(i % 2 ? 0.001 : 0.02))) << i;
}

TEST(UnobservedDirection, WidensAlongTheNewestWeakScansDirectionInMetresAndRadians) {
  UnobservedDirection tracker(params());
  // Half x translation, half a turn about z that moves points at 4 m by as much.
  Vector6d weak_direction = Vector6d::Zero();
  weak_direction(0) = std::sqrt(0.5);
  weak_direction(5) = std::sqrt(0.5);
  for (int i = 0; i < 10; ++i) tracker.add(weakest(0.001, weak_direction, 4.0));
  // A strong scan, its own weakest direction pinned (z): the unobserved one is still x and yaw.
  ASSERT_TRUE(tracker.add(weakest(0.01, Vector6d::Unit(2), 1.0)));
  Matrix6d covariance = Matrix6d::Identity() * 1e-6;
  tracker.widen(covariance);
  EXPECT_NEAR(covariance(0, 0), 1e-6 + 4.0 * 0.5, 1e-12);
  EXPECT_NEAR(covariance(5, 5), 1e-6 + 4.0 * 0.5 / 16.0, 1e-12);
  EXPECT_NEAR(covariance(0, 5), 4.0 * 0.5 / 4.0, 1e-12);
  EXPECT_NEAR(covariance(2, 2), 1e-6, 1e-15);
  EXPECT_TRUE(covariance.isApprox(covariance.transpose()));
}

TEST(UnobservedDirection, ABarOfZeroMarksNothing) {
  UnobservedDirectionParams p = params();
  p.weak_min_eigenvalue = 0.0;
  UnobservedDirection tracker(p);
  for (int i = 0; i < 30; ++i) EXPECT_FALSE(tracker.add(weakest(0.0))) << i;
}

TEST(UnobservedDirection, ParametersOutOfRangeAreNamed) {
  const auto throws_naming = [](UnobservedDirectionParams p, const std::string& name) {
    try {
      UnobservedDirection tracker(p);
      ADD_FAILURE() << name << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  UnobservedDirectionParams p = params();
  p.window_scans = 0;
  throws_naming(p, "window_scans");
  p = params();
  p.enter_fraction = 0.0;
  throws_naming(p, "enter_fraction");
  p = params();
  p.sigma_m = 0.0;
  throws_naming(p, "sigma_m");
  p = params();
  p.weak_min_eigenvalue = -1.0;
  throws_naming(p, "weak_min_eigenvalue");
}

}  // namespace
}  // namespace tumble
