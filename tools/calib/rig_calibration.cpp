#include "tools/calib/rig_calibration.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/angles.hpp"
#include "core/types.hpp"
#include "tools/calib/input_error.hpp"
#include "tools/calib/rig_bootstrap.hpp"
#include "tools/calib/run_inputs.hpp"

namespace tumble::calib {
namespace {

constexpr double kCoarseStepS = 0.001;
// After the coarse search, the first de-skewed pass searches this grid.
constexpr double kWideHalfWidthS = 0.04;
constexpr double kWideStepS = 0.001;
// Each pass searches the offset around the last estimate in two grids.
constexpr double kFineHalfWidthS = 0.008;
constexpr double kFineStepS = 0.0005;
constexpr double kFinerHalfWidthS = 0.0006;
constexpr double kFinerStepS = 0.0001;
constexpr std::size_t kMinIncrements = 50;
constexpr double kSettledOffsetS = 0.0001;
constexpr double kSettledRotationDeg = 0.02;
// Pass 1 ends when the lidar's scan-to-scan rotation and the gyro's differ
// in magnitude by more than this, this many times in a row.
constexpr double kBootstrapMismatchRad = 0.03;
constexpr std::size_t kBootstrapStopAfter = 3;
constexpr double kBootstrapMinWeakestAxisDeg = 0.1;
// Pass 1's refits register the recording's first seconds of motion after
// the lidar-only stretch: the gentle start, where a wrongly turned de-skew
// misleads ICP least, and short, so a refit takes seconds; 3 s adds ~30
// scans turning tens of degrees about every axis.
constexpr double kBootstrapWindowS = 3.0;
// The refit's fits from the even and from the odd scans (no scan in
// common) must agree within this: the later passes settle from a first
// rotation a degree off, not from one the recording does not determine.
constexpr double kBootstrapMaxDisagreementDeg = 1.0;

Eigen::Vector3d rotation_vector(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

RunSetup recording_setup(const std::filesystem::path& dir, const RigOptions& options) {
  const std::filesystem::path manifest = dir / "manifest.yaml";
  if (std::filesystem::exists(manifest)) return read_run_setup(manifest);
  RunSetup setup;
  setup.imu_rate_hz = options.imu_rate_hz;
  setup.imu_baud = options.imu_baud;
  setup.lidar_clock = options.lidar_clock;
  return setup;
}

RigPass evaluate_pass(const std::string& name, std::span<const ScanPose> poses, std::span<const ImuSample> imu,
                      double centre_s, double half_width_s, double step_s) {
  RigPass pass;
  pass.name = name;
  pass.scans = poses.size();
  for (const ScanPose& p : poses) pass.scans_registered += p.registered ? 1 : 0;
  const std::vector<LidarRotation> lidar = lidar_rotations(poses);
  pass.increments = lidar.size();
  if (lidar.size() < kMinIncrements) {
    std::ostringstream why;
    why << name << ": only " << lidar.size() << " pairs of consecutive registered scans (" << pass.scans_registered
        << " of " << pass.scans << " scans registered); at least " << kMinIncrements << " are needed";
    throw RigError(why.str());
  }
  pass.offset = fine_time_offset(lidar, imu, centre_s, half_width_s, step_s);
  pass.offset = fine_time_offset(lidar, imu, pass.offset.offset_s, kFinerHalfWidthS, kFinerStepS);
  pass.rotation = align_rotation_increments(rotation_increments(lidar, imu, pass.offset.offset_s));
  return pass;
}

}  // namespace

std::vector<LidarRotation> lidar_rotations(std::span<const ScanPose> poses) {
  std::vector<LidarRotation> out;
  for (std::size_t k = 1; k < poses.size(); ++k) {
    const ScanPose &a = poses[k - 1], &b = poses[k];
    const double period = b.t_scan_start_s - a.t_scan_start_s;
    // Consecutive scans only: a scan lost in between doubles the gap.
    if (!a.registered || !b.registered || !(period > 0) || period > 1.5 * (a.t_scan_end_s - a.t_scan_start_s))
      continue;
    out.push_back({a.t_s, b.t_s, rotation_vector(a.T_wl.linear().transpose() * b.T_wl.linear())});
  }
  return out;
}

RigCalibration calibrate_rig(const std::filesystem::path& dir, const RigOptions& options,
                             const RigProgress& progress) {
  if (!std::filesystem::is_directory(dir)) throw InputError(dir.string() + ": not a folder");
  const RunSetup setup = recording_setup(dir, options);
  const std::vector<ImuSample> imu = read_imu_samples(dir / "imu.pcap", setup);
  const OdometryParams params = rig_registration_params();
  RigCalibration out;
  out.imu_samples = imu.size();

  // Pass 1: lidar only, while it agrees with the gyro's rotation magnitudes.
  std::size_t disagreements = 0;
  const auto diverging = [&](const std::vector<ScanPose>& poses) {
    const std::vector<LidarRotation> last = lidar_rotations(std::span(poses).last(std::min<std::size_t>(2, poses.size())));
    if (last.empty()) {
      disagreements = poses.back().registered ? disagreements : disagreements + 1;
    } else {
      const double gyro_rad = rotation_increments(last, imu, 0.0).front().gyro_rad.norm();
      disagreements = std::abs(last.front().rotation_rad.norm() - gyro_rad) > kBootstrapMismatchRad ? disagreements + 1 : 0;
    }
    return disagreements >= kBootstrapStopAfter;
  };
  std::vector<ScanPose> poses = register_rig_scans(dir / "lidar.pcap", setup.lidar_clock, imu, std::nullopt, params, {}, diverging);
  if (disagreements >= kBootstrapStopAfter) poses.resize(poses.size() - kBootstrapStopAfter);
  const std::vector<LidarRotation> lidar1 = lidar_rotations(poses);
  {
    std::vector<RotationIncrement> lidar_only;
    for (const LidarRotation& l : lidar1) lidar_only.push_back({l.rotation_rad, Eigen::Vector3d::Zero(), 0.0});
    out.bootstrap_weakest_axis_deg = std::sqrt(std::max(weakest_axis_excitation_rad2(lidar_only), 0.0)) * kRadToDeg;
    out.bootstrap_s = poses.empty() ? 0.0 : poses.back().t_s - poses.front().t_s;
  }
  if (lidar1.size() < 3 || out.bootstrap_weakest_axis_deg < kBootstrapMinWeakestAxisDeg) {
    std::ostringstream why;
    why << "the lidar-only registration agreed with the gyro for " << out.bootstrap_s
        << " s only, turning at most " << out.bootstrap_weakest_axis_deg
        << " deg RMS per scan about its least-turned axis (" << kBootstrapMinWeakestAxisDeg
        << " needed): start the recording at rest and build the motion about every axis up over a second or two";
    throw RigError(why.str());
  }
  // Refined on the recording's first seconds (rig_bootstrap.hpp: why it holds).
  const double window_end_s = poses.back().t_s + kBootstrapWindowS;
  const double window_s = window_end_s - poses.front().t_s;
  std::vector<ScanPose> window = poses;  // the last registration's (its velocities de-skew the next)
  const RefinedBootstrap refined =
      refine_bootstrap(bootstrap_rotation(poses, imu), imu, [&](const GyroModel& gyro) {
        window = register_rig_scans(dir / "lidar.pcap", setup.lidar_clock, imu, gyro, params, window,
                                    [&](const std::vector<ScanPose>& p) { return p.back().t_s >= window_end_s; });
        return window;
      });
  if (!refined.settled) {
    std::ostringstream why;
    why << "pass 1: the first rotation did not settle over the recording's first " << window_s << " s ("
        << refined.refits << " refits, the last moved it by " << refined.last_move_deg
        << " deg): start the recording at rest and build the motion about every axis up over a second or two";
    throw RigError(why.str());
  }
  const BootstrapRotation& bootstrap = refined.fit;
  poses = refined.poses;
  if (bootstrap.halves_disagreement_deg > kBootstrapMaxDisagreementDeg) {
    std::ostringstream why;
    why << "pass 1: the rotations from the even and from the odd scans of the recording's first "
        << window_s << " s differ by " << bootstrap.halves_disagreement_deg << " deg (at most "
        << kBootstrapMaxDisagreementDeg << " allowed): the recording does not determine the rotation";
    throw RigError(why.str());
  }
  RigPass pass;
  pass.scans = poses.size();
  for (const ScanPose& p : poses) pass.scans_registered += p.registered ? 1 : 0;
  pass.increments = bootstrap.pairs;
  pass.rotation = bootstrap.rotation;
  // The best shift is not the rig's offset (the window was de-skewed at
  // offset 0, which pulls it there): the next pass searches the offset.
  std::ostringstream label;
  label << std::setprecision(2) << "pass 1 (lidar only, then " << refined.refits
        << " gyro de-skewed refits over the first " << window_s
        << " s, pairs of scans up to 1 s apart; best agreement at " << std::lround(bootstrap.lag_s * 1e3)
        << " ms; its even and odd scans agree within " << bootstrap.halves_disagreement_deg << " deg)";
  pass.name = label.str();
  if (progress) progress(pass);
  out.passes.push_back(pass);

  // De-skewed passes, until the estimate settles.
  for (int i = 0; i < options.max_deskewed_passes; ++i) {
    const RigPass& previous = out.passes.back();
    const GyroModel gyro{previous.rotation.R_li, GyroTiming{.offset_s = previous.offset.offset_s,
                                                            .bias_rad_s = previous.rotation.gyro_bias_rad_s}};
    poses = register_rig_scans(dir / "lidar.pcap", setup.lidar_clock, imu, gyro, params, poses);
    const std::string name = "pass " + std::to_string(i + 2) + " (gyro de-skew)";
    if (i == 0) {
      const TimeOffsetEstimate coarse =
          coarse_time_offset(lidar_rotations(poses), imu, 0.0, options.max_offset_s, kCoarseStepS);
      if (coarse.at_edge) {
        std::ostringstream why;
        why << "the time offset is beyond the searched +-" << options.max_offset_s << " s (best at "
            << coarse.offset_s << " s, rate correlation " << coarse.score << ")";
        throw RigError(why.str());
      }
      // The magnitudes' correlation peak is broad and, with the first
      // rotation still degrees off, tens of ms out: the residual decides
      // over a wider grid first.
      const TimeOffsetEstimate wide =
          fine_time_offset(lidar_rotations(poses), imu, coarse.offset_s, kWideHalfWidthS, kWideStepS);
      pass = evaluate_pass(name, poses, imu, wide.offset_s, kFineHalfWidthS, kFineStepS);
    } else {
      pass = evaluate_pass(name, poses, imu, gyro.timing.offset_s, kFineHalfWidthS, kFineStepS);
    }
    if (progress) progress(pass);
    out.passes.push_back(pass);
    const double turn_deg =
        Eigen::AngleAxisd(pass.rotation.R_li.transpose() * gyro.R_li).angle() * kRadToDeg;
    if (i >= 1 && std::abs(pass.offset.offset_s - gyro.timing.offset_s) < kSettledOffsetS &&
        turn_deg < kSettledRotationDeg)
      break;
  }
  out.rotation = pass.rotation;
  out.offset = pass.offset;
  const GyroModel final_gyro{out.rotation.R_li,
                             GyroTiming{.offset_s = out.offset.offset_s, .bias_rad_s = out.rotation.gyro_bias_rad_s}};
  out.lever_arm = estimate_lever_arm(poses, imu, final_gyro);
  // Earth's gravity varies by ±0.03 m/s² with place: within the check's 0.05 m/s².
  out.lever_arm_observable = out.lever_arm.solved &&
                             out.lever_arm.sigma_m.maxCoeff() <= options.max_lever_arm_sigma_m &&
                             std::abs(out.lever_arm.gravity_m_s2 - kStandardGravity_m_s2) <= options.max_gravity_error_m_s2;
  return out;
}

}  // namespace tumble::calib
