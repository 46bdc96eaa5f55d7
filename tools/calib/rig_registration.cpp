#include "tools/calib/rig_registration.hpp"

#include <algorithm>
#include <cmath>

#include "core/trajectory.hpp"
#include "tools/calib/run_inputs.hpp"

namespace tumble::calib {
namespace {

constexpr std::size_t kTrajectoryCapacity = 256;
constexpr double kPredictionStepS = 0.005;  // trajectory samples inside a scan

// A constant twist from the last two registered poses.
struct Prediction {
  Eigen::Isometry3d T_wl = Eigen::Isometry3d::Identity();
  double t_s = 0.0;
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d omega_l = Eigen::Vector3d::Zero();
  bool valid = false;
};

Eigen::Isometry3d extrapolate(const Prediction& p, double t_s) {
  const double dt = t_s - p.t_s;
  Eigen::Isometry3d T = p.T_wl;
  T.translation() += p.v_w * dt;
  const double angle = p.omega_l.norm() * dt;
  if (angle > 1e-12) T.linear() = p.T_wl.linear() * Eigen::AngleAxisd(angle, p.omega_l.normalized()).toRotationMatrix();
  return T;
}

void push(Trajectory& trajectory, double t_s, const Eigen::Isometry3d& T, const Eigen::Vector3d& v_w,
          const Eigen::Vector3d& omega_l) {
  TrajectorySample s;
  s.t_s = t_s;
  s.q_wl = Eigen::Quaterniond(T.linear());
  s.p_w = T.translation();
  s.v_w = v_w;
  s.omega_l = omega_l;
  trajectory.push_back(s);
}

// The lidar's motion over [t0, t1] as a trajectory for de-skewing and
// prediction: rotation from the gyro (conjugated into the lidar frame) when
// there is a gyro model, else the constant twist; translation at constant
// velocity.
// The mean velocity over the scan starting at t0 from a previous pass (the
// same scans: its poses at the same times), in that pass's lidar frame at t0.
std::optional<Eigen::Vector3d> scan_velocity_l(std::span<const ScanPose> previous, double t0) {
  const auto it = std::lower_bound(previous.begin(), previous.end(), t0 - 1e-6,
                                   [](const ScanPose& p, double t) { return p.t_s < t; });
  if (it == previous.end() || it + 1 == previous.end() || std::abs(it->t_s - t0) > 1e-6) return std::nullopt;
  const ScanPose &a = *it, &b = *(it + 1);
  if (!a.registered || !b.registered || !(b.t_s > a.t_s) || b.t_s - a.t_s > 1.5 * (a.t_scan_end_s - a.t_scan_start_s))
    return std::nullopt;
  return a.T_wl.linear().transpose() * (b.T_wl.translation() - a.T_wl.translation()) / (b.t_s - a.t_s);
}

void predict(const Prediction& last, const std::optional<GyroModel>& gyro, std::span<const ImuSample> imu,
             std::span<const ScanPose> previous, double t0, double t1, Trajectory& trajectory) {
  trajectory.clear();
  Eigen::Isometry3d start = last.valid ? extrapolate(last, t0) : last.T_wl;
  if (gyro && last.valid) {
    start.linear() = last.T_wl.linear() * gyro->R_li *
                     gyro_rotation(imu, gyro->timing, last.t_s, t0).toRotationMatrix() * gyro->R_li.transpose();
  }
  // The velocity over the scan: the previous pass's, where it has one (no
  // lag), else the last interval's (lags the motion by a scan interval: its
  // de-skew error grows with the acceleration and would bias the lever arm).
  const std::optional<Eigen::Vector3d> v_l = scan_velocity_l(previous, t0);
  const Eigen::Vector3d v_w = v_l ? Eigen::Vector3d(start.linear() * *v_l) : last.v_w;
  for (double t = t0;; t += kPredictionStepS) {
    const double tc = std::min(t, t1);
    Eigen::Isometry3d T = last.valid ? extrapolate(last, tc) : start;
    if (v_l) T.translation() = start.translation() + v_w * (tc - t0);
    Eigen::Vector3d omega_l = last.omega_l;
    if (gyro) {
      T.linear() = start.linear() * gyro->R_li * gyro_rotation(imu, gyro->timing, t0, tc).toRotationMatrix() *
                   gyro->R_li.transpose();
      omega_l = gyro->R_li * gyro_rate_at(imu, gyro->timing, tc);
    }
    push(trajectory, tc, T, v_w, omega_l);
    if (tc >= t1) break;
  }
}

}  // namespace

OdometryParams rig_registration_params() {
  OdometryParams p;
  p.weights.model = WeightModel::NM;
  p.reading_normal_source = ReadingNormalSource::kScanLines;
  // The passes de-skew with a gyro model still being fitted: beams traced
  // with it would clear map points that are there. The calibration's scene
  // holds still (docs/robot-setup.md, step 4).
  p.seen_through.enabled = false;
  return p;
}

std::vector<ScanPose> register_rig_scans(const std::filesystem::path& lidar_pcap, rs16::ClockMode lidar_clock,
                                         std::span<const ImuSample> imu,
                                         const std::optional<GyroModel>& gyro, const OdometryParams& params,
                                         std::span<const ScanPose> previous, const StopCheck& stop) {
  ScanRegistration registration(params);
  Trajectory trajectory(kTrajectoryCapacity, params.fuser.speed_uncertainty);
  ScanResult result;
  std::vector<ScanPose> poses;
  Prediction last;  // the newest pose (registered or predicted), and the twist into it
  bool stopped = false;
  std::size_t scans_seen = 0, most_points = 0;
  for_each_scan(lidar_pcap, lidar_clock, [&](const Scan& scan) {
    if (stopped) return;
    // The recording's first scan is a part of a turn, and so is any scan
    // with packets lost: a sliver would start (or mislead) the map.
    most_points = std::max(most_points, scan.points.size());
    if (scans_seen++ == 0 || scan.points.size() < most_points / 2) return;
    const double t0 = scan.points.front().t_s, t1 = scan.points.back().t_s;
    predict(last, gyro, imu, previous, t0, t1, trajectory);
    if (registration.process(scan, trajectory, result) != ScanOutcome::Registered) return;
    const ScanPose pose{t0, t0, t1, result.T_wl, result.registered};
    if (last.valid && pose.registered && t0 > last.t_s) {
      const double dt = t0 - last.t_s;
      last.v_w = (pose.T_wl.translation() - last.T_wl.translation()) / dt;
      const Eigen::AngleAxisd turn(last.T_wl.linear().transpose() * pose.T_wl.linear());
      last.omega_l = turn.angle() * turn.axis() / dt;
    }
    last.T_wl = pose.T_wl;
    last.t_s = t0;
    last.valid = true;
    poses.push_back(pose);
    stopped = stop && stop(poses);
  });
  return poses;
}

}  // namespace tumble::calib
