#include "daemon/core_stages.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/angles.hpp"
#include "core/registration_confidence.hpp"
#include "daemon/viewer_messages.hpp"
#include "tumble/scan_t.hpp"

namespace tumble::daemon {

namespace {

double steady_now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::uint8_t to_bits(const std::array<bool, 3>& axes) {
  return static_cast<std::uint8_t>((axes[0] ? 1 : 0) | (axes[1] ? 2 : 0) | (axes[2] ? 4 : 0));
}

std::array<bool, 3> from_bits(std::uint8_t bits) { return {(bits & 1) != 0, (bits & 2) != 0, (bits & 4) != 0}; }

// The newest record at or before t_s (the first when none is).
const TrajectoryRecord& record_at(std::span<const TrajectoryRecord> trajectory, double t_s) {
  const auto after = std::upper_bound(trajectory.begin(), trajectory.end(), t_s,
                                      [](double t, const TrajectoryRecord& r) { return t < r.t_s; });
  return after == trajectory.begin() ? trajectory.front() : *(after - 1);
}

// A loss of track whose cause may be the fuser's velocity: the fuser drops
// it and waits for the robot to rest (ImuFuser::restart_at_rest).
bool restarts_at_rest(TrackingLoss reason) {
  return reason == TrackingLoss::NotRegistered || reason == TrackingLoss::DisagreesWithImu ||
         reason == TrackingLoss::TooFast || reason == TrackingLoss::MovingAtRest;
}

// Predicting from the registrations needs the newest to be this recent.
constexpr double kMaxPredictionAge_s = 0.5;
// A lidar gap (10 Hz scans) this long: the next scans are checked against the IMU.
constexpr double kLidarGapToCheck_s = 0.25;
constexpr int kScansCheckedAfterLidarGap = 5;
// How far an IMU-propagated pose may be off after a lidar gap of g seconds:
// kTranslationSlack_m + kVelocityError_m_s · g and kRotationSlack_rad + kRateError_rad_s · g.
constexpr double kTranslationSlack_m = 0.1;
constexpr double kVelocityError_m_s = 0.5;
constexpr double kRotationSlack_rad = 0.05;
constexpr double kRateError_rad_s = 0.05;
// Scans in a row not registered or not trusted before the local map is given up.
constexpr int kScansToReset = 3;

// The longest stretch without a fused sample over [start_s, end_s].
double imu_hole_s(std::span<const TrajectoryRecord> trajectory, double start_s, double end_s) {
  if (trajectory.empty()) return std::numeric_limits<double>::infinity();
  double hole = std::max({0.0, end_s - trajectory.back().t_s, trajectory.front().t_s - start_s});
  for (std::size_t i = 1; i < trajectory.size(); ++i)
    if (trajectory[i].t_s > start_s && trajectory[i - 1].t_s < end_s)
      hole = std::max(hole, trajectory[i].t_s - trajectory[i - 1].t_s);
  return hole;
}

// The RS-16's spin axis. An error in the rate about it stretches the
// de-skewed scan along its own azimuth, which a registration hardly sees: at
// 10 rad/s on the turntable it settled 4.7° a scan short, every scan, with a
// low residual and a full inlier ratio, and ended 165° off.
constexpr std::uint8_t kLidarZ = 1u << 2;

// The lidar axes (bit 0 = x) the gyro clipped about during the span.
std::uint8_t gyro_clipped_axes(std::span<const TrajectoryRecord> trajectory, double start_s, double end_s) {
  std::uint8_t axes = 0;
  for (const TrajectoryRecord& r : trajectory)
    if (r.t_s >= start_s && r.t_s <= end_s) axes |= r.gyro_saturated_axes;
  return axes;
}

}  // namespace

TrajectoryRecord to_record(const TrajectorySample& s) {
  TrajectoryRecord r;
  r.t_s = s.t_s;
  r.q_wl_wxyz = {s.q_wl.w(), s.q_wl.x(), s.q_wl.y(), s.q_wl.z()};
  r.p_w_m = {s.p_w.x(), s.p_w.y(), s.p_w.z()};
  r.v_w_m_s = {s.v_w.x(), s.v_w.y(), s.v_w.z()};
  r.omega_l_rad_s = {s.omega_l.x(), s.omega_l.y(), s.omega_l.z()};
  r.velocity_var_m2_s2 = {s.velocity_var_w_m2_s2.x(), s.velocity_var_w_m2_s2.y(), s.velocity_var_w_m2_s2.z()};
  r.gyro_saturated_axes = to_bits(s.gyro_saturated);
  r.accel_saturated_axes = to_bits(s.accel_saturated);
  return r;
}

TrajectorySample to_sample(const TrajectoryRecord& r) {
  TrajectorySample s;
  s.t_s = r.t_s;
  s.q_wl = Eigen::Quaterniond(r.q_wl_wxyz[0], r.q_wl_wxyz[1], r.q_wl_wxyz[2], r.q_wl_wxyz[3]);
  s.p_w = Eigen::Vector3d(r.p_w_m[0], r.p_w_m[1], r.p_w_m[2]);
  s.v_w = Eigen::Vector3d(r.v_w_m_s[0], r.v_w_m_s[1], r.v_w_m_s[2]);
  s.omega_l = Eigen::Vector3d(r.omega_l_rad_s[0], r.omega_l_rad_s[1], r.omega_l_rad_s[2]);
  s.velocity_var_w_m2_s2 = Eigen::Vector3d(r.velocity_var_m2_s2.data());
  s.gyro_saturated = from_bits(r.gyro_saturated_axes);
  s.accel_saturated = from_bits(r.accel_saturated_axes);
  for (std::size_t k = 0; k < 3; ++k) s.saturated[k] = s.gyro_saturated[k] || s.accel_saturated[k];
  return s;
}

// ---- fuser ------------------------------------------------------------------------

CoreFuserStage::CoreFuserStage(const OdometryParams& params) : params_(params), fuser_(params.fuser) {
  const double var = params.min_position_sigma_m * params.min_position_sigma_m;
  position_var_m2_ = {var, var, var};
}

TrajectoryRecord CoreFuserStage::record_of(const TrajectorySample& sample) const {
  TrajectoryRecord r = to_record(sample);
  r.position_var_m2 = position_var_m2_;
  r.lidar_corrected = fuser_.stats().velocity_updates > 0;
  r.attitude_from_device = params_.fuser.attitude_from_device;
  r.resets = resets_;
  r.imu_bridged = fuser_.stats().reanchors > reanchors_corrected_;
  r.awaiting_rest = fuser_.awaiting_rest();
  r.rests = static_cast<std::uint32_t>(fuser_.stats().rests);
  r.velocity_unconfirmed = !fuser_.velocity_confirmed();
  r.runaways_at_rest = static_cast<std::uint32_t>(fuser_.stats().runaways_at_rest);
  return r;
}

bool CoreFuserStage::add_imu(const ImuSample& sample, TrajectoryRecord& out) {
  fuser_.add_imu(sample);
  if (!fuser_.initialized() || fuser_.trajectory().empty()) return false;
  const TrajectorySample& newest = fuser_.trajectory().back();
  if (newest.t_s <= newest_published_s_) return false;  // the sample was dropped (out of order)
  newest_published_s_ = newest.t_s;
  out = record_of(newest);
  return true;
}

void CoreFuserStage::add_correction(const RegistrationRecord& registration,
                                    const std::function<void(const TrajectoryRecord&)>& republish) {
  if (registration.resets > resets_ && restarts_at_rest(registration.reset_reason)) fuser_.restart_at_rest();
  resets_ = registration.resets;
  if (!registration.registered || !fuser_.initialized()) return;
  // The registered pose's published covariance: it grows where the scan hardly constrains the pose.
  for (std::size_t k = 0; k < 3; ++k) position_var_m2_[k] = registration.covariance[k * 7];
  const CorrectionResult result = fuser_.correct_with_registered_pose(registration.correction);
  if (std::isnan(result.rewritten_after_s)) return;
  reanchors_corrected_ = fuser_.stats().reanchors;
  // The registration thread reads trajectory windows from what was published:
  // publish the rewritten tail again (it supersedes the older records).
  const Trajectory& trajectory = fuser_.trajectory();
  std::size_t first = trajectory.size();
  while (first > 0 && trajectory[first - 1].t_s > result.rewritten_after_s) --first;
  for (std::size_t i = first; i < trajectory.size(); ++i) republish(record_of(trajectory[i]));
}

// ---- registration -----------------------------------------------------------------

CoreRegistrationStage::CoreRegistrationStage(const OdometryParams& params, const rs16::ScanAssemblerConfig& scans,
                                             double lidar_silent_to_reset_s, std::size_t threads,
                                             std::function<void(std::size_t)> on_helper_start)
    : params_(params),
      min_scan_coverage_(scans.min_scan_coverage),
      assembler_(scans,
                 [this](Scan& scan, const rs16::ScanReport& report) {
                   if (scan.points.empty()) return;
                   // Told once the scan is whole: a packet that only came late is not lost.
                   if (scan.missing_packets > 0)
                     fault_log_.warn("lost packets", scan.points.back().t_s,
                                     "lidar: scan {} lost {} MSOP packets; {} so far", scan.index,
                                     scan.missing_packets, assembly_stats_.missing_packets);
                   if (report.cut_at_bound) {
                     // Not a turn of the head: the motor stalled or slowed, or the azimuths are corrupt.
                     fault_log_.warn("cut scan", scan.points.back().t_s,
                                     "lidar: scan {} ran {} revolutions at {} rpm ({} points) without passing the "
                                     "split azimuth (motor stalled?): cut and skipped; {} so far",
                                     scan.index, rs16::kMaxScanRevolutions, rs16::kSlowestRpm, scan.points.size(),
                                     assembly_stats_.scans_cut_at_bound);
                     return;
                   }
                   if (report.short_coverage) {
                     // Registered as if whole, a part of a turn weighs too little
                     // against the map and may slide along it. The first scan
                     // starts wherever the head was: no fault, so not warned of.
                     if (scan.index > 0)
                       fault_log_.warn("short scan", scan.points.back().t_s,
                                       "lidar: scan {} covers {:.0f} % of a turn (lidar.min_scan_coverage {:.0f} %): "
                                       "skipped; {} so far",
                                       scan.index, report.azimuth_coverage * 100.0, min_scan_coverage_ * 100.0,
                                       assembly_stats_.scans_short_coverage);
                     return;
                   }
                   held_.index = scan.index;
                   held_.missing_packets = scan.missing_packets;
                   std::swap(held_.points, scan.points);  // the assembler reuses our previous vector
                   holding_ = true;
                 }),
      pool_(threads, std::move(on_helper_start)),
      registration_(params, steady_now_s, pool_),
      trajectory_(params.fuser.trajectory_capacity, params.fuser.speed_uncertainty),
      prediction_(256, params.fuser.speed_uncertainty),
      lidar_silent_to_reset_s_(lidar_silent_to_reset_s) {}

std::vector<std::string> CoreRegistrationStage::stage_names() const {
  return {"deskew", "downsample", "normals", "weights", "icp_matching", "icp_solve", "seen_through", "map_update"};
}

bool CoreRegistrationStage::add_points(const PointBlock& block) {
  const rs16::DecoderStats before = assembly_stats_;
  assembler_.add(block, assembly_stats_);
  warn_of_packet_faults(before, block.t_s);
  return holding_;
}

void CoreRegistrationStage::warn_of_packet_faults(const rs16::DecoderStats& before, double now_s) {
  const rs16::DecoderStats& now = assembly_stats_;
  if (now.duplicate_packets > before.duplicate_packets)
    fault_log_.warn("duplicate packets", now_s, "lidar: duplicated MSOP packet dropped; {} so far",
                    now.duplicate_packets);
  if (now.late_packets > before.late_packets)
    fault_log_.warn("late packets", now_s, "lidar: MSOP packet out of order: put into its scan; {} so far",
                    now.late_packets);
  if (now.late_packets_dropped > before.late_packets_dropped)
    fault_log_.warn("late packets dropped", now_s,
                    "lidar: MSOP packet out of order, its scan already handed on: dropped; {} so far",
                    now.late_packets_dropped);
}

RegistrationStage::TimeSpan CoreRegistrationStage::held_scan_span() const {
  return {held_.points.front().t_s, held_.points.back().t_s};
}

void CoreRegistrationStage::discard_held_scan() { holding_ = false; }

void CoreRegistrationStage::report(PipelineCounters& counters) const {
  constexpr auto relaxed = std::memory_order_relaxed;
  counters.lidar_missing_packets.store(static_cast<std::int64_t>(assembly_stats_.missing_packets), relaxed);
  counters.lidar_duplicate_packets.store(static_cast<std::int64_t>(assembly_stats_.duplicate_packets), relaxed);
  counters.lidar_late_packets.store(static_cast<std::int64_t>(assembly_stats_.late_packets), relaxed);
  counters.lidar_late_packets_dropped.store(static_cast<std::int64_t>(assembly_stats_.late_packets_dropped),
                                            relaxed);
  counters.scans_short_coverage.store(static_cast<std::int64_t>(assembly_stats_.scans_short_coverage), relaxed);
  counters.scans_cut_at_bound.store(static_cast<std::int64_t>(assembly_stats_.scans_cut_at_bound), relaxed);
}

void CoreRegistrationStage::register_held_scan(std::span<const TrajectoryRecord> trajectory, RegistrationRecord& out,
                                               tumble::scan_t* viewer_scan) {
  holding_ = false;
  out = RegistrationRecord{};
  out.t_s = held_.points.front().t_s;
  out.t_end_s = held_.points.back().t_s;
  out.scan_index = static_cast<std::int64_t>(held_.index);
  out.model = params_.weights.model;
  out.deskew = params_.deskew;
  out.points_in = static_cast<std::int32_t>(held_.points.size());
  out.resets = resets_;
  out.reset_reason = reset_reason_;
  if (trajectory.empty()) return;  // the fuser has not initialised: nothing to register with
  const double t_end_s = held_.points.back().t_s;
  trajectory_.clear();
  for (const TrajectoryRecord& r : trajectory) trajectory_.push_back(to_sample(r));
  const Eigen::Vector3d velocity_w_m_s = trajectory_.velocity_at(out.t_s);
  const TrajectoryRecord& at_start = record_at(trajectory, out.t_s);
  ScanConditions conditions{.deskew = params_.deskew};
  const Trajectory* motion = &trajectory_;
  if (imu_hole_s(trajectory, out.t_s, t_end_s) > params_.fuser.max_imu_gap_s &&
      predict_from_registrations(out.t_s, t_end_s)) {
    motion = &prediction_;
    conditions.trajectory_measured = false;
    out.imu_bridged = true;
  }
  // A bridged scan is de-skewed with the registrations' prediction, not the gyro.
  const std::uint8_t clipped_axes = out.imu_bridged ? 0 : gyro_clipped_axes(trajectory, out.t_s, t_end_s);
  out.spin_rate_unmeasured = (clipped_axes & kLidarZ) != 0;
  const double lidar_gap_s = out.t_s - previous_scan_start_s_;
  const double lidar_silent_s = out.t_s - previous_scan_end_s_;
  previous_scan_start_s_ = out.t_s;
  previous_scan_end_s_ = t_end_s;
  if (lidar_silent_s > lidar_silent_to_reset_s_ && newest_pose_) {
    forget_poses_and_reset_map(TrackingLoss::LidarSilent);
    out.resets = resets_;
    out.reset_reason = reset_reason_;
  } else if (lidar_gap_s > kLidarGapToCheck_s && newest_pose_) {
    scans_to_check_ = kScansCheckedAfterLidarGap;
    spin_clipped_scans_in_row_ = 0;
  }
  // A clipped spin settles on the registrations the fuser took its rate from
  // during it: the count restarts after a lidar gap, a new map and a scan
  // not registered (scan_verdict.cpp).
  spin_clipped_scans_in_row_ = out.spin_rate_unmeasured ? spin_clipped_scans_in_row_ + 1 : 0;
  out.spin_clipped_scans_in_row = spin_clipped_scans_in_row_;
  if (scans_to_check_ > 0 && !out.imu_bridged) {
    const double since_registered_s = out.t_s - newest_pose_->t_s;
    conditions.max_translation_m = kTranslationSlack_m + kVelocityError_m_s * since_registered_s;
    conditions.max_rotation_rad = kRotationSlack_rad + kRateError_rad_s * since_registered_s;
    --scans_to_check_;
  }
  const Eigen::Isometry3d predicted = motion->pose_at(out.t_s);
  const auto report_unregistered = [&] {
    spin_clipped_scans_in_row_ = 0;
    result_ = ScanResult{};
    result_.T_wl = predicted;
    result_.t_scan_start_s = out.t_s;
    result_.points_in = held_.points.size();
    fill_record(result_, velocity_w_m_s, out);
  };
  // After a loss of track the fuser drops its velocity and waits for the
  // robot to rest; a new map started before then would be built on the
  // velocity that misled the last one.
  if (rests_before_loss_) {
    if (at_start.awaiting_rest || at_start.rests <= *rests_before_loss_) {
      report_unregistered();
      out.awaiting_rest = true;
      return;
    }
    rests_before_loss_.reset();
  }
  // The first map starts only from a scan the gyro measured whole. A clipped
  // axis is a lower bound, and until a scan has registered on a map the
  // fuser has no lidar rate to stand in for it: the first scan would be
  // de-skewed and placed a tenth of a turn short (the default run, its map
  // started 0.4 s into the pull: 55 m off, reported only as weakly
  // constrained). After that, a new map starts with the fuser's last lidar
  // rate, however old.
  if (registration_.map().empty() && !registered_on_a_map_ && clipped_axes != 0) {
    report_unregistered();
    out.map_deferred = true;
    return;
  }
  switch (registration_.process(held_, *motion, result_, conditions)) {
    case ScanOutcome::Registered:
      break;
    case ScanOutcome::TooSmall:
    case ScanOutcome::OutOfOrder:
      report_unregistered();
      return;
  }
  // Registrations that agree with a wrong prediction confirm the velocity
  // that made it, and in a scene weak along one axis nothing stops them: a
  // speed no robot reaches is the runaway's one sure sign.
  // The same sign, found still: the IMU says the robot rests, the registrations that it moves.
  const std::uint32_t runaways_at_rest = trajectory.back().runaways_at_rest;
  if (speed_limit_applies_ && velocity_w_m_s.norm() > params_.fuser.max_speed_m_s) {
    forget_poses_and_reset_map(TrackingLoss::TooFast);
    out.awaiting_rest = true;
  } else if (runaways_at_rest > runaways_at_rest_seen_) {
    forget_poses_and_reset_map(TrackingLoss::MovingAtRest);
    out.awaiting_rest = true;
  } else {
    keep_track(result_);
  }
  runaways_at_rest_seen_ = runaways_at_rest;
  out.velocity_unconfirmed = at_start.velocity_unconfirmed;
  if (resets_ > out.resets && restarts_at_rest(reset_reason_)) rests_before_loss_ = trajectory.back().rests;
  out.resets = resets_;
  out.reset_reason = reset_reason_;
  out.untrusted = result_.rejected;
  fill_record(result_, velocity_w_m_s, out);
  if (viewer_scan != nullptr)
    fill_viewer_scan(registration_.reading(), result_.T_wl, result_.t_scan_start_s, result_.scan_index, *viewer_scan);
}

bool CoreRegistrationStage::predict_from_registrations(double t_start_s, double t_end_s) {
  if (!newest_pose_ || !previous_pose_ || t_start_s - newest_pose_->t_s > kMaxPredictionAge_s) return false;
  const Pose& a = *newest_pose_;
  const Pose& b = *previous_pose_;
  const double dt_s = a.t_s - b.t_s;
  if (!(dt_s > 0.0)) return false;
  const Eigen::Vector3d v_w = (a.T_wl.translation() - b.T_wl.translation()) / dt_s;
  const Eigen::AngleAxisd turn(b.T_wl.rotation().transpose() * a.T_wl.rotation());
  const Eigen::Vector3d omega_l = turn.angle() * turn.axis() / dt_s;
  const Eigen::Quaterniond q_a(a.T_wl.rotation());
  constexpr int kSteps = 20;
  prediction_.clear();
  for (int i = 0; i <= kSteps; ++i) {
    TrajectorySample s;
    s.t_s = t_start_s + (t_end_s - t_start_s) * i / kSteps;
    const Eigen::Vector3d rotation = omega_l * (s.t_s - a.t_s);
    const Eigen::Quaterniond step = rotation.norm() > 0
                                        ? Eigen::Quaterniond(Eigen::AngleAxisd(rotation.norm(), rotation.normalized()))
                                        : Eigen::Quaterniond::Identity();
    s.q_wl = (q_a * step).normalized();
    s.p_w = a.T_wl.translation() + v_w * (s.t_s - a.t_s);
    s.v_w = v_w;
    s.omega_l = omega_l;
    prediction_.push_back(s);
  }
  return true;
}

void CoreRegistrationStage::keep_track(const ScanResult& result) {
  if (result.registered) {
    if (!result.map_initialised) registered_on_a_map_ = true;
    scans_lost_in_a_row_ = 0;
    previous_pose_ = newest_pose_;
    newest_pose_ = Pose{result.t_scan_start_s, result.T_wl};
    // Through an unobserved spell the map took points at poses nothing
    // measured along that direction: a corridor's stretched or shifted.
    // Scans that pin the direction again (the corridor's end) would
    // register well on it, and be published as good, while the pose slides
    // with the map's error. A new map starts with the next scan instead.
    if (result.unobserved_spell_ended) reset_map(TrackingLoss::UnobservedMap);
    return;
  }
  spin_clipped_scans_in_row_ = 0;
  if (++scans_lost_in_a_row_ < kScansToReset) return;
  reset_map(result.rejected ? TrackingLoss::DisagreesWithImu : TrackingLoss::NotRegistered);
}

// The registered poses no longer predict the next scan (the IMU alone carried
// the pose, or the velocity ran away): no prediction from them either.
void CoreRegistrationStage::forget_poses_and_reset_map(TrackingLoss reason) {
  reset_map(reason);
  newest_pose_.reset();
  previous_pose_.reset();
}

// The poses already published are kept; the next scan starts a new map at the
// fuser's pose, which carries on from them.
void CoreRegistrationStage::reset_map(TrackingLoss reason) {
  registration_.reset_map();
  ++resets_;
  reset_reason_ = reason;
  speed_limit_applies_ = reason != TrackingLoss::LidarSilent;
  scans_lost_in_a_row_ = 0;
  scans_to_check_ = 0;
  spin_clipped_scans_in_row_ = 0;
}

void CoreRegistrationStage::fill_record(const ScanResult& result, const Eigen::Vector3d& velocity_w_m_s,
                                        RegistrationRecord& out) {
  const Eigen::Vector3d p = result.T_wl.translation();
  const Eigen::Quaterniond q(result.T_wl.rotation());
  out.position_m = {p.x(), p.y(), p.z()};
  out.orientation_wxyz = {q.w(), q.x(), q.y(), q.z()};
  out.velocity_m_s = {velocity_w_m_s.x(), velocity_w_m_s.y(), velocity_w_m_s.z()};
  const Matrix6d& covariance = result.covariance_published;
  for (int i = 0; i < 36; ++i) out.covariance[static_cast<std::size_t>(i)] = covariance(i / 6, i % 6);
  out.expected_error_m = static_cast<float>(result.expected_error_m);
  out.expected_error_icp_m = static_cast<float>(result.expected_error_icp_m);
  out.expected_rotation_error_icp_rad = static_cast<float>(result.expected_rotation_error_icp_rad);
  out.iterations = result.iterations;
  out.registered = result.registered;
  out.map_initialised = result.map_initialised;
  out.converged = result.converged;
  out.correction = scan_correction_of(result);
  out.jumped = result.jumped;
  for (int i = 0; i < 3; ++i)
    out.held_translation_w[static_cast<std::size_t>(i)] = static_cast<float>(result.held_translation_w[i]);
  out.prediction_prior = result.prediction_prior;
  out.weak_translation_predicted = result.weak_translation_predicted;
  out.inlier_ratio = static_cast<float>(result.inlier_ratio);
  out.matched_ratio = static_cast<float>(result.matched_ratio);
  out.correction_m = static_cast<float>(result.correction_w.norm());
  out.correction_deg = static_cast<float>(result.rotation_from_prediction_rad * kRadToDeg);
  out.residual_m = static_cast<float>(result.residual_rms_m);
  out.degeneracy = static_cast<float>(result.degeneracy.min_eigenvalue);
  out.direction_unobserved = result.direction_unobserved;
  for (int k = 0; k < 3; ++k) out.correction_w_m[k] = static_cast<float>(result.correction_w[k]);
  out.points_used = static_cast<std::int32_t>(result.points_registered);
  out.map_points = static_cast<std::int32_t>(result.map_points);
  out.map_points_seen_through = static_cast<std::int32_t>(result.map_points_seen_through);

  const PointCloud& reading = registration_.reading();
  if (result.points_downsampled > 0 && !reading.sigma_s_m.empty()) {
    sigma_scratch_.assign(reading.sigma_s_m.begin(), reading.sigma_s_m.end());
    const auto middle = sigma_scratch_.begin() + static_cast<std::ptrdiff_t>(sigma_scratch_.size() / 2);
    std::nth_element(sigma_scratch_.begin(), middle, sigma_scratch_.end());
    out.sigma_s_median_m = *middle;
    out.sigma_s_max_m = *std::max_element(sigma_scratch_.begin(), sigma_scratch_.end());
  }
  const StageTimings& t = result.timings;
  const double stages_s[] = {t.deskew_s,         t.downsample_s, t.normals_s,   t.weights_s,
                             t.icp_matching_s, t.icp_solve_s,  t.seen_through_s, t.map_update_s};
  out.num_stages = static_cast<std::uint8_t>(std::size(stages_s));
  for (std::size_t i = 0; i < std::size(stages_s); ++i) out.stage_ms[i] = static_cast<float>(stages_s[i] * 1e3);
}

void CoreRegistrationStage::fill_viewer_map(tumble::map_t& map) const {
  daemon::fill_viewer_map(registration_.map(), result_.t_scan_start_s, result_.scan_index, resets_, map);
}

}  // namespace tumble::daemon
