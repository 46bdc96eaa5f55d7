#include "tools/calib/run_evaluation.hpp"

#include <algorithm>
#include <exception>

#include "core/deskew.hpp"
#include "core/imu_fuser.hpp"
#include "tools/calib/ground_truth.hpp"
#include "tools/calib/input_error.hpp"
#include "tools/calib/run_inputs.hpp"

namespace tumble::calib {
namespace {

bool clipped_between(const Trajectory& trajectory, double t0_s, double t1_s) {
  for (std::size_t i = trajectory.size(); i-- > 0;) {
    const TrajectorySample& s = trajectory[i];
    if (s.t_s < t0_s) break;
    if (s.t_s <= t1_s && std::any_of(s.saturated.begin(), s.saturated.end(), [](bool b) { return b; })) return true;
  }
  return false;
}

// Pass 1: the reference map from the ground-truth de-skewed scans.
void build_reference_map(const BenchRun& run, const RunSetup& setup, const GroundTruth& truth, ReferenceMap& map) {
  for_each_scan(run.dir / "lidar.pcap", setup.lidar_clock, [&](const Scan& scan) {
    if (!truth.covers(scan.points.front().t_s, scan.points.back().t_s)) return;
    std::size_t hint = 0;
    for (const LidarPoint& p : scan.points) map.add(truth.pose_at(p.t_s, hint) * Eigen::Vector3d(p.x_m, p.y_m, p.z_m));
  });
  map.finish();
}

// Pass 2: the odometry over the run, each scan measured as it is de-skewed.
void run_odometry(const BenchRun& run, const RunSetup& setup, const std::vector<ImuSample>& imu,
                  const GroundTruth& truth, const ReferenceMap& map, const CalibParams& params, RunOutcome& out) {
  OdometryParams odometry = params.odometry;
  odometry.fuser.T_li = setup.T_li;
  const auto seconds_of_samples = static_cast<std::size_t>(4.0 * setup.imu_rate_hz);  // as tumbled sizes them
  odometry.fuser.history_capacity = std::max(odometry.fuser.history_capacity, seconds_of_samples);
  odometry.fuser.trajectory_capacity = std::max(odometry.fuser.trajectory_capacity, seconds_of_samples);
  ImuFuser fuser(odometry.fuser);
  ScanRegistration registration(odometry);
  ScanResult result;
  std::vector<Eigen::Vector3d> deskewed;
  const Eigen::Vector3d motion_w = truth.travel_direction();
  const double t0_s = truth.t_begin_s();
  const double motion_start_s = truth.motion_start_s();
  std::size_t next_imu = 0;

  out.scans_decoded = for_each_scan(run.dir / "lidar.pcap", setup.lidar_clock, [&](const Scan& scan) {
    const double t_first_s = scan.points.front().t_s;
    const double t_last_s = scan.points.back().t_s;
    const Trajectory& trajectory = fuser.trajectory();
    auto covered = [&] { return fuser.initialized() && !trajectory.empty() && trajectory.t_end_s() >= t_last_s; };
    while (next_imu < imu.size() && !covered()) fuser.add_imu(imu[next_imu++]);
    if (!covered() || t_first_s < trajectory.t_begin_s()) {
      ++out.scans_without_trajectory;
      return;
    }
    deskewed.resize(scan.points.size());
    deskew_scan(scan, trajectory, true, deskewed);
    const bool saturated = clipped_between(trajectory, t_first_s, t_last_s);

    const bool registered =
        registration.process(scan, trajectory, result) == ScanOutcome::Registered && result.registered;
    if (registered)
      fuser.correct_with_registered_pose(scan_correction_of(result));
    else
      ++out.scans_not_registered;

    if (!truth.covers(t_first_s, t_last_s)) {
      ++out.scans_without_truth;
      return;
    }
    const ScanResidual r = measure_scan_residual(scan, deskewed, truth, run.rig, motion_w, map, params.residual);
    ScanRecord record;
    record.scan_index = scan.index;
    record.t_start_s = t_first_s - t0_s;
    record.duration_s = t_last_s - t_first_s;
    record.speed = run.rig == Rig::Rail ? truth.mean_linear_speed_m_s(t_first_s, t_last_s)
                                        : truth.mean_angular_rate_rad_s(t_first_s, t_last_s);
    record.mean_range_m = r.mean_range_m;
    record.residual_m = r.residual_m;
    record.residual_rms_m = r.residual_rms_m;
    record.residual_points = r.residual_points;
    record.deskew_error_m = r.deskew_error_m;
    record.deskew_error_points = r.deskew_error_points;
    record.registered = registered;
    record.saturated = saturated;
    record.before_motion = t_last_s < motion_start_s;
    out.scans.push_back(record);
  });
}

}  // namespace

OdometryParams CalibParams::default_odometry() {
  OdometryParams p;
  p.weights.model = WeightModel::NM;
  return p;
}

RunOutcome evaluate_run(const BenchRun& run, const CalibParams& params) {
  RunOutcome out;
  out.name = run.name;
  out.rig = run.rig;
  try {
    if (run.rig == Rig::Other) throw InputError(run.name + ": kind \"" + run.kind + "\" is not a calibration rig");
    if (!std::filesystem::is_directory(run.dir)) throw InputError(run.dir.string() + ": missing run folder");
    const RunSetup setup = read_run_setup(run.dir / "manifest.yaml");
    const GroundTruth truth = GroundTruth::load(run.dir / "ground_truth.tum");
    const std::vector<ImuSample> imu = read_imu_samples(run.dir / "imu.pcap", setup);
    ReferenceMap map(params.map);
    build_reference_map(run, setup, truth, map);
    out.map_points = map.size();
    run_odometry(run, setup, imu, truth, map, params, out);
    out.ok = true;
  } catch (const InputError& e) {
    out.problem = e.what();
  } catch (const std::exception& e) {
    out.problem = run.name + ": " + e.what();
  }
  if (!out.ok) out.scans.clear();
  return out;
}

}  // namespace tumble::calib
