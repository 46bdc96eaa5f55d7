// The registration alone on a simulated run (tumble-sim, decoded by the RS-16
// driver): with the simulator's exact motion as the trajectory, de-skewing is
// perfect and the registered poses must not drift; without de-skewing, the
// same scans drift clearly more. The trajectory carries only the motion's
// shape: each scan's is the ground truth re-anchored at the previous
// registered pose (what the fuser does after each correction), so every
// registration error accumulates as in odometry.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/scan_registration.hpp"
#include "test/core/synthetic_room.hpp"
#include "test/core_sim/simulated_scans.hpp"
#include "tools/sim/scenario.hpp"
#include "tools/sim/sim_run.hpp"

namespace tumble {
namespace {

// The rolling cage pulled along the garage's lane at 10 rad/s (2.5 m/s) for
// 2 s, its first scans at rest, with two seeded jolts to 11 rad/s.
sim::Scenario rolling_cage_scenario() {
  const std::string yaml =
      "scene: garage\n"
      "motion:\n"
      "  type: rolling_cage\n"
      "  origin: {xyz_m: [-12, 0, 0]}\n"
      "  radius_m: 0.25\n"
      "  roll:\n"
      "    - hold_s: 0.25\n"
      "    - ramp: {to_rad_s: 10, peak_rad_s2: 40, rise_s: 0.05}\n"
      "    - hold_s: 2.0\n"
      "  seed: 3\n"
      "  min_gap_s: 0.2\n"
      "  jolts: {count: 2, swing_rad_s: [0.5, 1.0], peak_rad_s2: [400, 800]}\n"
      "seed: 5\n";
  return sim::parse_scenario(YAML::Load(yaml), "gt_deskew.yaml", sim::sim_data_dir("scenarios"));
}

struct Drift {
  double translation_cm_per_m = 0;
  double rotation_deg_per_m = 0;
  double distance_m = 0;
  std::size_t scans = 0;
  std::size_t unregistered = 0;
};

Drift register_run(const sim::SimRun& run, const std::vector<Scan>& scans, bool deskew) {
  OdometryParams params;
  params.deskew = deskew;
  ScanRegistration registration(params);
  const test::GroundTruthReplay replay = test::register_with_ground_truth(run, scans, registration);
  // The first scan was mapped at the truth, so the last pose's error is the drift.
  const Eigen::Isometry3d truth = test::truth_at(run, replay.last_t_s).T_wb;
  Drift drift;
  drift.distance_m = replay.distance_m;
  drift.scans = replay.scans;
  drift.unregistered = replay.unregistered;
  drift.translation_cm_per_m = 100 * (replay.last_registered.translation() - truth.translation()).norm() / drift.distance_m;
  drift.rotation_deg_per_m = test::rotation_error_rad(replay.last_registered, truth) * 180 / M_PI / drift.distance_m;
  return drift;
}

TEST(RegistrationOnSimulatedRun, WithGroundTruthDeskewTheDriftIsNearZeroAndWithoutItClearlyWorse) {
  // Unoptimised, the simulator's rays cost ~0.2 ms each: 4 usable scans take
  // 18 s (ASan), too few for a drift and too slow for the suite.
  if (test::kCoarseTests) GTEST_SKIP() << "simulating a run takes minutes in unoptimised builds";
  const sim::SimRun run(rolling_cage_scenario());
  const std::vector<Scan> scans = test::simulate_scans(run);
  ASSERT_GE(scans.size(), 20u);

  const Drift with = register_run(run, scans, true);
  const Drift without = register_run(run, scans, false);
  std::printf("over %.2f m in %zu scans: de-skewed %.3f cm/m %.4f deg/m, raw %.3f cm/m %.4f deg/m\n",
              with.distance_m, with.scans, with.translation_cm_per_m, with.rotation_deg_per_m,
              without.translation_cm_per_m, without.rotation_deg_per_m);
  EXPECT_GT(with.distance_m, 4.0);
  EXPECT_EQ(with.unregistered, 0u);
  EXPECT_LT(with.translation_cm_per_m, 1.0);
  EXPECT_LT(with.rotation_deg_per_m, 0.1);
  EXPECT_GT(without.translation_cm_per_m, 3 * with.translation_cm_per_m);
  EXPECT_GT(without.rotation_deg_per_m, 3 * with.rotation_deg_per_m);
}

}  // namespace
}  // namespace tumble
