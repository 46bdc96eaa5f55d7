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
#include "drivers/rs16/driver.hpp"
#include "test/core/synthetic_room.hpp"
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

// Every complete revolution of the run, as the driver assembles it.
std::vector<Scan> simulate_scans(const sim::SimRun& run) {
  std::vector<Scan> scans;
  // 28 800 returns per revolution; a few are dropped or out of range.
  rs16::Driver driver(rs16::DriverConfig{}, [&](Scan& scan, const rs16::ScanReport& report) {
    if (!report.ended_by_gap && scan.points.size() > 20000) scans.push_back(scan);
  });
  sim::LidarStream stream = run.lidar_stream();
  sim::LidarDatagram datagram;
  const double epoch_s = 1e-9 * static_cast<double>(run.scenario().epoch_ns);
  while (stream.next(datagram)) {
    rs16::LidarDatagram d;
    d.kind = datagram.is_difop ? rs16::PacketKind::Difop : rs16::PacketKind::Msop;
    d.arrival_s = epoch_s + 1e-9 * static_cast<double>(datagram.arrival_ns);
    d.payload = datagram.payload;
    driver.on_datagram(d);
  }
  if (!scans.empty()) scans.erase(scans.begin());  // the first may have started mid-revolution
  return scans;
}

struct Drift {
  double translation_cm_per_m = 0;
  double rotation_deg_per_m = 0;
  double distance_m = 0;
  std::size_t scans = 0;
  std::size_t unregistered = 0;
};

// Registers every scan with the ground truth, re-anchored at the previous
// registered pose, as the trajectory (1 kHz, so the jolts are resolved).
Drift register_run(const sim::SimRun& run, const std::vector<Scan>& scans, bool deskew) {
  OdometryParams params;
  params.deskew = deskew;
  ScanRegistration registration(params);
  const double epoch_s = 1e-9 * static_cast<double>(run.scenario().epoch_ns);
  auto truth_at = [&](double t_s) { return run.motion().at(t_s - epoch_s); };

  Drift drift;
  Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();  // registered pose · truth⁻¹ at the last scan start
  Eigen::Isometry3d last_registered = Eigen::Isometry3d::Identity();
  double last_t_s = 0;
  ScanResult result;
  for (const Scan& scan : scans) {
    const double t0 = scan.points.front().t_s, t1 = scan.points.back().t_s;
    Trajectory trajectory(static_cast<std::size_t>((t1 - t0) / 1e-3) + 16, SpeedUncertaintyParams{});
    for (double t = t0 - 2e-3; t < t1 + 3e-3; t += 1e-3) {
      const sim::MotionState s = truth_at(t);
      const Eigen::Isometry3d T = anchor * s.T_wb;
      TrajectorySample sample;
      sample.t_s = t;
      sample.q_wl = Eigen::Quaterniond(T.linear());
      sample.p_w = T.translation();
      sample.v_w = anchor.linear() * s.v_w;
      sample.omega_l = s.omega_b;
      trajectory.push_back(sample);
    }
    if (registration.process(scan, trajectory, result) != ScanOutcome::Registered || !result.registered) {
      ++drift.unregistered;
    }
    anchor = result.T_wl * truth_at(t0).T_wb.inverse();
    if (drift.scans > 0) {
      drift.distance_m += (truth_at(t0).T_wb.translation() - truth_at(last_t_s).T_wb.translation()).norm();
    }
    last_registered = result.T_wl;
    last_t_s = t0;
    ++drift.scans;
  }
  // The first scan was mapped at the truth, so the last pose's error is the drift.
  const Eigen::Isometry3d truth = truth_at(last_t_s).T_wb;
  drift.translation_cm_per_m = 100 * (last_registered.translation() - truth.translation()).norm() / drift.distance_m;
  drift.rotation_deg_per_m = test::rotation_error_rad(last_registered, truth) * 180 / M_PI / drift.distance_m;
  return drift;
}

TEST(RegistrationOnSimulatedRun, WithGroundTruthDeskewTheDriftIsNearZeroAndWithoutItClearlyWorse) {
  // Unoptimised, the simulator's rays cost ~0.2 ms each: 4 usable scans take
  // 18 s (ASan), too few for a drift and too slow for the suite.
  if (test::kCoarseTests) GTEST_SKIP() << "simulating a run takes minutes in unoptimised builds";
  const sim::SimRun run(rolling_cage_scenario());
  const std::vector<Scan> scans = simulate_scans(run);
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
