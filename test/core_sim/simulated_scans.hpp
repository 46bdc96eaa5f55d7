// A simulated run's scans, as the RS-16 driver assembles them, and the
// registration of those scans with the simulator's exact motion as the
// trajectory. The trajectory carries only the motion's shape: each scan's is
// the ground truth re-anchored at the previous registered pose (what the
// fuser does after each correction), so every registration error
// accumulates as in odometry.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "core/scan_registration.hpp"
#include "drivers/rs16/driver.hpp"
#include "tools/sim/sim_run.hpp"

namespace tumble::test {

// The driver's clock at the run's time 0: scan times minus this are run times.
inline double epoch_s(const sim::SimRun& run) { return 1e-9 * static_cast<double>(run.scenario().epoch_ns); }

// Every complete revolution of the run, the first (which may have started mid-revolution) left out.
inline std::vector<Scan> simulate_scans(const sim::SimRun& run) {
  std::vector<Scan> scans;
  // 28 800 returns per revolution; a few are dropped or out of range.
  rs16::Driver driver(rs16::DriverConfig{}, [&](Scan& scan, const rs16::ScanReport& report) {
    if (!report.ended_by_gap && scan.points.size() > 20000) scans.push_back(scan);
  });
  sim::LidarStream stream = run.lidar_stream();
  sim::LidarDatagram datagram;
  const double epoch = epoch_s(run);
  while (stream.next(datagram)) {
    rs16::LidarDatagram d;
    d.kind = datagram.is_difop ? rs16::PacketKind::Difop : rs16::PacketKind::Msop;
    d.arrival_s = epoch + 1e-9 * static_cast<double>(datagram.arrival_ns);
    d.payload = datagram.payload;
    driver.on_datagram(d);
  }
  if (!scans.empty()) scans.erase(scans.begin());
  return scans;
}

// The simulator's motion at a scan time.
inline sim::MotionState truth_at(const sim::SimRun& run, double t_s) {
  return run.motion().at(t_s - epoch_s(run));
}

struct GroundTruthReplay {
  std::size_t scans = 0;
  std::size_t unregistered = 0;
  double distance_m = 0;  // travelled between the first and the last scan's start
  Eigen::Isometry3d last_registered = Eigen::Isometry3d::Identity();
  double last_t_s = 0;  // the last scan's start
};

// Registers every scan with the ground truth, re-anchored at the previous
// registered pose, as the trajectory (1 kHz, so jolts are resolved). The map
// starts at the truth: registered poses are in the simulator's world frame.
// after_scan(result) runs after each scan.
inline GroundTruthReplay register_with_ground_truth(const sim::SimRun& run, const std::vector<Scan>& scans,
                                                    ScanRegistration& registration,
                                                    const std::function<void(const ScanResult&)>& after_scan = {}) {
  GroundTruthReplay replay;
  Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();  // registered pose · truth⁻¹ at the last scan start
  ScanResult result;
  for (const Scan& scan : scans) {
    const double t0 = scan.points.front().t_s, t1 = scan.points.back().t_s;
    Trajectory trajectory(static_cast<std::size_t>((t1 - t0) / 1e-3) + 16, SpeedUncertaintyParams{});
    for (double t = t0 - 2e-3; t < t1 + 3e-3; t += 1e-3) {
      const sim::MotionState s = truth_at(run, t);
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
      ++replay.unregistered;
    }
    if (after_scan) after_scan(result);
    anchor = result.T_wl * truth_at(run, t0).T_wb.inverse();
    if (replay.scans > 0) {
      replay.distance_m +=
          (truth_at(run, t0).T_wb.translation() - truth_at(run, replay.last_t_s).T_wb.translation()).norm();
    }
    replay.last_registered = result.T_wl;
    replay.last_t_s = t0;
    ++replay.scans;
  }
  return replay;
}

}  // namespace tumble::test
