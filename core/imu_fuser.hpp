// The 100 Hz fuser (paper §III-B, docs/method.md §1): IMU samples in, the lidar
// trajectory T_WL(t) out, re-anchored by the 10 Hz registration.
//
// Frames. W: the lidar frame at initialisation, levelled with gravity (z up,
// the lidar's heading kept, origin at the lidar). I: the IMU. L: the lidar.
// T_LI (config) maps IMU coordinates into the lidar frame; the fuser tracks
// the IMU and outputs the LIDAR: p_WL = p_WI + R_WI p_IL, and the lever arm
// gives v_WL = v_WI + R_WI (ω_I × p_IL).
//
// 1. Initialisation: waits for `static_duration_s` of samples that look
//    static (gyro and accelerometer steady; any motion restarts the window).
//    The mean accelerometer gives the gravity direction (→ roll, pitch; yaw 0)
//    and the gravity magnitude the filter will subtract; the mean gyro is the
//    gyro bias.
// 2. Attitude: Madgwick (gyro + gated accelerometer) at every sample, or the
//    device's own orientation when `attitude_from_device` (aligned to W once,
//    at the first sample that carries one). Ours: the accelerometer's step is
//    left out while a scan registered on a map, within
//    `levelling_max_expected_error_m` or with its attitude within
//    `levelling_max_rotation_error_rad`, levelled the attitude less than
//    `accel_correction_after_s` before the sample; the gyro alone
//    carries it from one registration to the next (0.01° of drift in 0.1 s).
//    The accelerometer measures gravity only when nothing accelerates the
//    IMU: a turntable's centripetal 1.6 m/s² (4 rad/s, 0.1 m off the axis)
//    passes the gate, leans Madgwick's "up" by 9° and its step pulls the
//    attitude that way by 0.57° per scan, which the de-skew carries into
//    every point. Without such registrations (before the first map, lost,
//    the lidar silent, a scan that pins the pose only weakly and may turn it
//    wrongly) the accelerometer is the only tilt reference and
//    levels it as in the paper. The rule goes by data time. A correction
//    re-bases the attitude steps of the samples up to the first one at or
//    after the scan's end (the ones a lossless replay holds when the
//    registration is done) and takes every later step again from the
//    corrected attitude, as a sample arriving after the correction is
//    stepped: the result is that of a registration done at that sample,
//    however many samples came first (thread timing, live). Not with the
//    device's attitude, whose re-based steps keep their bits as taken.
// 3. Velocity: a linear Kalman filter per W axis: state v, input the
//    gravity-free acceleration a_W = R_WI f + g (trapezoid), process noise
//    PSD = accel_noise_density² + accel_unmodelled² · 1 s. The second term is
//    ours: a filter whose only state is v cannot estimate the slowly varying
//    errors (gravity leaked through a 0.6° attitude error is 0.1 m/s²); with
//    the datasheet density alone (60 µg/√Hz) it would trust the IMU ~10⁴×
//    more than the lidar and never remove a drift.
//    Measurement: the lidar's mean velocity over the last scan interval,
//    (p_k − p_{k−1}) / (t_k − t_{k−1}) from the last two registered poses,
//    applied at its true time, the middle of the interval t_m, by
//    re-propagating the buffered samples since t_m. Our refinement: the
//    innovation is the lidar mean minus the FILTER's mean over the same
//    interval (not minus v(t_m)); both are equal under constant acceleration,
//    but a shock inside the interval makes v(t_m) differ from the mean by
//    metres per second while the filter's error is still linear. Noise: the
//    two poses' position sigmas, R = (σ_k² + σ_{k−1}²) / Δt².
// 4. Position: the fused velocity integrated (trapezoid) at the IMU rate.
// 5. Pose correction: the registered pose is more accurate than integration,
//    so the fuser is re-anchored at the scan start t_k: position set to the
//    registered one there, attitude rotated by ΔR = R_reg(t_k) R_fused(t_k)⁻¹
//    for the samples from t_k to the first one past the scan's end (the
//    gyro's relative rotation is kept; later samples are stepped again, 2)
//    and the velocity after t_k re-integrated with the corrected attitude.
//    The trajectory gets a sample at t_k itself, so it passes exactly through the
//    registered pose there (a later re-propagation that starts before t_k
//    rebuilds from the IMU samples and drops it; that scan is registered by
//    then); the only discontinuity is in the IMU interval that ends at t_k,
//    before the start of a scan that is already registered.
//    Every later scan starts after t_k, and de-skewing uses only the motion
//    within a scan, so it never sees a jump.
// 6. Saturation: a clipped gyro axis only says |ω| ≥ range there. The
//    MTi-30's range is 450 deg/s (7.85 rad/s) and a rolling cage turns at up
//    to 11 rad/s, so integrating the clipped value would lose up to ~0.3 rad
//    per scan of attitude, and with it the ICP's initial guess and the
//    de-skew. Ours: on a clipped axis the fuser uses the lidar's rate
//    instead, the mean body rate between the last two registered poses
//    (constant velocity), when it has the clipped reading's sign and a larger
//    magnitude; otherwise the clipped value (the reading is a lower bound).
//    Each correction re-integrates the clipped samples after the registered
//    scan with the new rate (the other samples up to the scan's end keep
//    Madgwick's steps, 2).
//    Clipping is flagged through to the samples: gyro clipping per lidar
//    axis for that sample; accelerometer clipping adds process noise
//    (saturated_accel_sigma along the clipped axis in W) and marks the W axes
//    it touches as "speed unknown" until a lidar velocity update measures them.
//    "Touches" = a direction cosine above 0.1 (the IMU→lidar and W→lidar
//    axis mappings use the same threshold).
//
// 7. IMU gaps (ours): while the IMU is silent the registration
//    predicts each scan from the registered poses themselves; their
//    corrections come after the newest sample and are kept as anchors. When
//    samples return after a gap longer than max_imu_gap_s with an anchor in
//    it, the fuser starts again from the newest anchor, carried to the
//    sample by the motion between the last two registered poses (constant
//    velocity and body rate), instead of integrating one sample across the
//    gap. The history starts again there, its velocity no better known than
//    bridged_velocity_sigma_m_s: those registrations were not de-skewed and
//    their velocity is a guess, which must not hold the next scans (the
//    registration's prior follows the velocity's variance), and the next
//    velocity measurement spans two scans the IMU covered, not an anchor.
// 8. Jumps: a scan whose registered pose is far from the prediction (a
//    ScanCorrection marked `jumped`) re-anchors the pose but is no velocity
//    measurement: either the prediction or the registration is wrong, and a
//    velocity taken across it carries the error into every later
//    prediction, which the next scans then confirm. The velocity's
//    variance rises to what the jump says it may be wrong by, so the next
//    interval measures it afresh.
// 9. Lost (restart_at_rest): a velocity carried from a runaway is what
//    misled the registration, so it is dropped: the position is held, the
//    attitude goes on (gyro and accelerometer), and the fuser waits for the
//    robot to be still for rest_duration_s, as at start-up. Then the
//    velocity is zero, the attitude is levelled again from the still
//    accelerometer (the heading kept) and the gyro bias is the still mean;
//    rests() counts up, which lets the registration start a new map.
//
// 10. After an IMU gap (7) the velocity is the registrations' alone, and
//    in a scene that repeats along an axis (parked cars, pillars) a scan
//    fits as well a car's length off and the next ones follow the velocity
//    that put it there. So it is unconfirmed (velocity_confirmed()) until
//    a still window of rest_duration_s, once no correction can rewrite it,
//    finds the fused speed at or below max_speed_at_rest_m_s; above it,
//    the velocity ran away with registrations that agreed with it, and
//    runaways_at_rest counts up (the daemon drops the map and restarts at
//    rest, 9). Only then: to the IMU a cruise at constant velocity looks
//    still (a rail cart at 3.5 m/s), so a still window is no proof of rest
//    while the IMU has measured the velocity all along.
//
// Bounded: the IMU history is a fixed ring (`history_capacity` samples, a few
// seconds at up to 1 kHz) and so is the output trajectory. No allocation per
// sample or per correction after construction.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/angles.hpp"
#include "core/madgwick.hpp"
#include "core/ring_buffer.hpp"
#include "core/speed_uncertainty.hpp"
#include "core/trajectory.hpp"
#include "core/types.hpp"

namespace tumble {

struct ImuFuserParams {
  // x_L = T_li · x_I: the IMU's pose in the lidar frame (extrinsic).
  Eigen::Isometry3d T_li = Eigen::Isometry3d::Identity();

  double static_duration_s = 1.0;
  // The still window that ends a wait for rest after a loss (header, 9):
  // shorter than the start-up's, so tracking resumes early in a rest.
  double rest_duration_s = 0.5;
  double static_max_gyro_rad_s = 0.1;           // ‖ω‖ above this is motion
  double static_accel_tolerance_m_s2 = 0.5;     // ‖a − window mean‖ or |‖a‖ − 9.80665| above: motion

  MadgwickParams madgwick;
  // Madgwick's accelerometer step only on samples this long after the newest
  // scan registered on a map (header, 2); 0: on every sample, as the paper.
  double accel_correction_after_s = 0.5;
  double levelling_max_expected_error_m = 0.024;  // of ScanResult::expected_error_icp_m (registration_confidence.hpp)
  // Or when its attitude is this certain (ScanResult::expected_rotation_error_icp_rad):
  // a corridor's scans pin the attitude (0.06-0.1°) but not the position
  // along its axis, and with the accelerometer's step a walker's 0.8 m/s²
  // along it tilted the attitude 5° (docs/decisions/attitude-between-scans.md).
  double levelling_max_rotation_error_rad = 0.15 * kDegToRad;
  bool attitude_from_device = false;

  double accel_noise_density_m_s2_sqrt_hz = 60e-6 * kStandardGravity_m_s2;  // MTi-30 datasheet
  double accel_unmodelled_m_s2 = 0.1;
  double saturated_accel_sigma_m_s2 = 100.0;    // how far beyond the range a clipped axis may be
  double initial_velocity_sigma_m_s = 0.01;     // after the static period
  double max_lidar_interval_s = 0.5;            // longer scan gaps give no velocity measurement
  double max_imu_gap_s = 0.1;                   // longer sample gaps are integrated but counted
  // The velocity after re-anchoring across an IMU gap (header, 7).
  double bridged_velocity_sigma_m_s = 1.0;
  // Faster than the robot ever moves, falls included: a fused velocity
  // beyond it is a runaway, and the daemon restarts the fuser at the next rest.
  double max_speed_m_s = 6.0;
  // After an IMU gap, a still window's fused speed above this: the velocity ran away (header, 10).
  double max_speed_at_rest_m_s = 0.3;
  // A scan's position along ScanCorrection::unmeasured_w is the prediction,
  // not a measurement: the velocity measurement from it is this uncertain
  // there (per W axis, by the direction's share of it), so it neither pulls
  // the velocity nor shrinks its variance.
  double unmeasured_position_sigma_m = 1.0;

  std::size_t history_capacity = 4096;
  std::size_t trajectory_capacity = 4096;
  SpeedUncertaintyParams speed_uncertainty;
};

struct ImuFuserStats {
  std::uint64_t samples = 0;                     // accepted, after initialisation
  std::uint64_t samples_out_of_order = 0;        // t not after the previous sample: dropped
  std::uint64_t imu_gaps = 0;                    // dt > max_imu_gap_s
  std::uint64_t static_restarts = 0;             // motion during the static window
  std::uint64_t accel_gated = 0;                 // Madgwick correction skipped (gate or clipping)
  std::uint64_t gyro_saturated_samples = 0;
  std::uint64_t gyro_samples_from_lidar = 0;     // clipped samples given the lidar's rate (header, 6)
  std::uint64_t accel_saturated_samples = 0;
  std::uint64_t pose_corrections = 0;
  std::uint64_t velocity_updates = 0;
  std::uint64_t corrections_before_init = 0;     // rejected
  std::uint64_t corrections_outside_history = 0; // rejected: t older than the history or newer than the IMU
  std::uint64_t velocity_updates_skipped = 0;    // interval too long, non-positive, or older than the history
  std::uint64_t anchors_while_imu_silent = 0;    // corrections newer than the newest sample (header, 7)
  std::uint64_t reanchors = 0;                   // restarts from an anchor after an IMU gap
  std::uint64_t jumps = 0;                       // corrections marked jumped: no velocity measurement (header, 8)
  std::uint64_t restarts_at_rest = 0;            // restart_at_rest() calls (header, 9)
  std::uint64_t rests = 0;                       // still windows that ended a wait for rest
  std::uint64_t corrections_awaiting_rest = 0;   // rejected: the fuser was waiting for rest
  std::uint64_t runaways_at_rest = 0;            // still windows after a gap with a fused speed beyond the limit (header, 10)
};

struct CorrectionResult {
  bool pose_reset = false;
  bool velocity_updated = false;
  // Trajectory samples after this time were rewritten (NaN: nothing changed).
  double rewritten_after_s = std::numeric_limits<double>::quiet_NaN();
};

// A registered scan, as the fuser takes it.
struct ScanCorrection {
  double t_start_s = 0.0;  // the scan's first point: the time of T_wl
  double t_end_s = 0.0;    // its last point
  Eigen::Isometry3d T_wl = Eigen::Isometry3d::Identity();  // the registered lidar pose at t_start_s
  double position_sigma_m = 0.0;  // the registration's residual mapped to a pose uncertainty
  // The scan's own position variance per W axis (its ICP covariance without
  // the prediction's prior): the velocity measurement is no better along an
  // axis than this, so a position the prior held is not a measured velocity.
  Eigen::Vector3d position_var_w_m2 = Eigen::Vector3d::Zero();
  // Far from the prediction (header, 8).
  bool jumped = false;
  bool map_start = false;         // it started a new map: its pose is the prediction itself
  double expected_error_m = 0.0;  // ScanResult::expected_error_icp_m
  // ScanResult::expected_rotation_error_icp_rad; unset, the attitude alone never levels.
  double expected_rotation_error_rad = std::numeric_limits<double>::infinity();
  // Unit, W axes: a translation the registration did not measure (it held
  // the prediction there, IcpParams::hold_weak_translation_share); zero: none.
  Eigen::Vector3d unmeasured_w = Eigen::Vector3d::Zero();
};

class ImuFuser {
 public:
  explicit ImuFuser(const ImuFuserParams& params);

  // One IMU sample (times must increase; others are dropped and counted).
  void add_imu(const ImuSample& sample);

  // The registration's result for a scan (ScanCorrection). Feeds the
  // velocity filter with the mean velocity since the previous registered
  // pose and re-anchors the trajectory (see the header). Call in scan order,
  // after the IMU data covers the scan's start (the pipeline needs that to
  // de-skew anyway); once it reaches the scan's end, the result no longer
  // depends on how far past it the samples go.
  // It levels the attitude (header, 2) unless it starts a new map or both
  // its expected error is above levelling_max_expected_error_m and its
  // attitude's above levelling_max_rotation_error_rad; it re-anchors either way.
  CorrectionResult correct_with_registered_pose(const ScanCorrection& scan);

  // Tracking was lost: drop the velocity and wait for rest (header, 9).
  void restart_at_rest();
  bool awaiting_rest() const { return awaiting_rest_; }
  // False from an IMU gap's re-anchoring to the next rest that finds the robot still (header, 10).
  bool velocity_confirmed() const { return velocity_confirmed_; }

  bool initialized() const { return initialized_; }
  const Trajectory& trajectory() const { return trajectory_; }
  const ImuFuserStats& stats() const { return stats_; }
  const Eigen::Vector3d& gyro_bias_rad_s() const { return gyro_bias_; }
  double gravity_m_s2() const { return gravity_m_s2_; }
  // Of the newest state: velocity variance per W axis ((m/s)²), for the odometry message.
  Eigen::Vector3d velocity_variance() const;

 private:
  struct KinematicState {
    Eigen::Vector3d v_w = Eigen::Vector3d::Zero();        // IMU velocity
    Eigen::Vector3d p_w = Eigen::Vector3d::Zero();        // IMU position
    Eigen::Vector3d v_integral = Eigen::Vector3d::Zero(); // ∫v dt (unaffected by position resets)
    Eigen::Vector3d variance = Eigen::Vector3d::Zero();   // of v, per W axis
    std::array<bool, 3> speed_unknown{};                  // per W axis, since an accelerometer clip
  };
  struct HistoryEntry {
    double t_s = 0.0;
    Eigen::Vector3d accel_i = Eigen::Vector3d::Zero();    // specific force as measured
    Eigen::Vector3d gyro_clipped_i = Eigen::Vector3d::Zero();  // bias removed, as measured
    Eigen::Vector3d gyro_i = Eigen::Vector3d::Zero();     // bias removed, clipped axes from the lidar's rate
    std::array<bool, 3> accel_clipped{};
    std::array<bool, 3> gyro_clipped{};
    Eigen::Quaterniond q_wi = Eigen::Quaterniond::Identity();
    Eigen::Vector3d accel_w = Eigen::Vector3d::Zero();    // gravity-free, in W
    KinematicState state;
  };
  struct VelocityMeasurement {
    double t_s = 0.0;
    Eigen::Vector3d innovation = Eigen::Vector3d::Zero();
    Eigen::Vector3d noise_variance = Eigen::Vector3d::Zero();  // per W axis
    // Per W axis: the unmeasured share of its variance (either end's
    // ScanCorrection::unmeasured_w) within the measured one's.
    std::array<bool, 3> measured{true, true, true};
  };
  struct PoseReset {
    double t_s = 0.0;
    double velocity_variance_floor_m2_s2 = 0.0;  // per W axis, from t_s on (header, 8)
    double t_scan_end_s = 0.0;
    Eigen::Quaterniond correction = Eigen::Quaterniond::Identity();  // ΔR
    Eigen::Quaterniond q_wi = Eigen::Quaterniond::Identity();        // registered
    Eigen::Vector3d p_wi = Eigen::Vector3d::Zero();
  };

  // Whether the sample completes a still window of `duration_s` (a moving
  // sample restarts it).
  bool completes_still_window(const ImuSample& sample, double duration_s);
  void restart_still_window();
  void accumulate_static(const ImuSample& sample);
  // One sample while waiting for rest (header, 9).
  void add_imu_awaiting_rest(const ImuSample& sample, const HistoryEntry& previous);
  void end_wait_at_rest(HistoryEntry& entry);
  // The fused speed of the still windows that no correction can rewrite any more (header, 10).
  void check_speeds_at_rest();
  // Whether a scan's registered pose corrects the fused state now; false
  // before initialisation, while waiting for rest, outside the history, or
  // when it is kept as an anchor while the IMU is silent (header, 7).
  bool takes_correction(const ScanCorrection& scan);
  // What the interval from the previous registration says of the velocity;
  // none after a jump, which floors the velocity's variance in `reset`
  // instead (header, 8).
  std::optional<VelocityMeasurement> velocity_from_registrations(const ScanCorrection& scan,
                                                                 const Eigen::Quaterniond& q_wi_registered,
                                                                 PoseReset& reset);
  void reanchor(const ImuSample& sample);
  void initialize(const ImuSample& last_sample);
  Eigen::Vector3d gravity_free_accel(const Eigen::Quaterniond& q_wi, const Eigen::Vector3d& accel_i) const;
  // The gyro a clipped sample most likely saw (header, 6).
  Eigen::Vector3d unclipped_gyro(const Eigen::Vector3d& gyro_clipped_i, const std::array<bool, 3>& clipped) const;
  void integrate(KinematicState& state, const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, double dt_s) const;
  void add_clip_noise(KinematicState& state, const HistoryEntry& entry, double dt_s) const;
  // A sample's readings as a history entry: bias removed, clipped gyro axes estimated.
  HistoryEntry measured_entry(const ImuSample& sample) const;
  // Index of the last history entry with t < t_s (requires t_s > the oldest).
  std::size_t entry_before(double t_s) const;
  KinematicState state_at(double t_s) const;
  Eigen::Quaterniond attitude_at(double t_s) const;
  // Whether Madgwick's accelerometer step applies to a sample at t_s (header, 2).
  bool accelerometer_levels(double t_s) const;
  // Advances `filter` over one sample's attitude step (header, 2); false when
  // the accelerometer's step was left out for clipping or the gate.
  bool step_attitude(MadgwickFilter& filter, const HistoryEntry& entry, double dt_s) const;
  void repropagate(const std::optional<VelocityMeasurement>& velocity, const PoseReset& reset);
  // What repropagate() carries from one rebuilt attitude to the next.
  struct AttitudeRebuild {
    MadgwickFilter filter;  // steps on from the rebuilt attitude after the scan's end
    std::optional<Eigen::Quaterniond> previous_q_before;  // the last entry's attitude as taken
    std::optional<Eigen::Quaterniond> previous_q_after;   // and as rebuilt
  };
  void rebuild_attitude(std::size_t n, std::size_t scan_end, const PoseReset& reset, AttitudeRebuild& rebuild);
  static void update_velocity(KinematicState& state, const VelocityMeasurement& velocity);
  TrajectorySample to_trajectory_sample(const HistoryEntry& entry) const;

  ImuFuserParams params_;
  Eigen::Quaterniond q_li_;
  Eigen::Vector3d p_il_;  // lidar origin in the IMU frame
  double process_noise_psd_;

  // Static window.
  double last_input_t_s_ = -std::numeric_limits<double>::infinity();
  double static_start_s_ = 0.0;
  std::size_t static_count_ = 0;
  Eigen::Vector3d static_accel_sum_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d static_gyro_sum_ = Eigen::Vector3d::Zero();

  bool initialized_ = false;
  double gravity_m_s2_ = kStandardGravity_m_s2;
  Eigen::Vector3d gyro_bias_ = Eigen::Vector3d::Zero();
  MadgwickFilter madgwick_;
  std::optional<Eigen::Quaterniond> device_alignment_;  // q_W←device frame

  RingBuffer<HistoryEntry> history_;
  Trajectory trajectory_;

  struct RegisteredPose {
    double t_s = 0.0;
    Eigen::Vector3d p_wi = Eigen::Vector3d::Zero();
    Eigen::Quaterniond q_wi = Eigen::Quaterniond::Identity();
    double sigma_m = 0.0;
    Eigen::Vector3d unmeasured_w = Eigen::Vector3d::Zero();  // ScanCorrection::unmeasured_w
    Eigen::Vector3d var_w_m2 = Eigen::Vector3d::Zero();       // ScanCorrection::position_var_w_m2
  };
  RegisteredPose registered_pose_of(const ScanCorrection& scan) const;
  std::optional<RegisteredPose> previous_registration_;
  std::optional<double> newest_levelling_s_;  // the newest registration on a map (header, 2)
  std::optional<RegisteredPose> anchor_;           // the newest correction after the newest sample
  std::optional<RegisteredPose> previous_anchor_;  // the one before it
  // Mean IMU body rate between the last two registered poses (header, 6).
  std::optional<Eigen::Vector3d> lidar_rate_i_rad_s_;
  bool awaiting_rest_ = false;
  bool velocity_confirmed_ = true;
  // Ends of still windows while the velocity is unconfirmed (header, 10): one
  // per rest_duration_s at most, checked within two scans; a full ring drops the oldest.
  RingBuffer<double> rests_to_check_{8};
  ImuFuserStats stats_;
};

}  // namespace tumble
