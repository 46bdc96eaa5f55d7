// Plain-data items that travel between the daemon's threads. Fixed size and
// allocation-free to copy, so rings of them never touch the heap.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/imu_fuser.hpp"
#include "core/point_weights.hpp"
#include "core/types.hpp"
#include "drivers/rs16/decoded_packet.hpp"

namespace tumble::daemon {

// The points of one lidar datagram, decoded on the io thread, with the block
// azimuths the registration thread's scan assembly splits on.
using PointBlock = rs16::DecodedPacket;

// One decoded IMU sample and when the io thread received the bytes that
// completed it (steady clock), for the arrival -> TUMBLE_ODOM latency.
struct ImuArrival {
  ImuSample sample;
  std::int64_t arrival_steady_ns = 0;
};

// One fused trajectory sample at IMU rate: the lidar pose T_WL(t) and its motion.
// Trivially copyable, as the seqlock trajectory buffer requires.
struct TrajectoryRecord {
  double t_s = 0.0;
  std::array<double, 4> q_wl_wxyz{1.0, 0.0, 0.0, 0.0};  // rotation W <- L
  std::array<double, 3> p_w_m{};
  std::array<double, 3> v_w_m_s{};
  std::array<double, 3> omega_l_rad_s{};  // in the lidar frame
  std::array<double, 3> position_var_m2{};
  std::array<double, 3> velocity_var_m2_s2{};
  std::uint8_t gyro_saturated_axes = 0;  // bit k = axis k clipped
  std::uint8_t accel_saturated_axes = 0;
  bool lidar_corrected = false;       // the velocity already includes a registered scan
  bool attitude_from_device = false;  // orientation is the IMU's own estimate, not Madgwick's
  std::int64_t imu_arrival_steady_ns = 0;  // ImuArrival::arrival_steady_ns of the sample; 0: unknown
  std::int32_t resets = 0;                 // odometry re-initialisations the fuser has seen
  bool imu_bridged = false;                // re-anchored on registered poses after an IMU gap, not yet corrected
  // Tracking was lost and the fuser waits for the robot to rest: the velocity
  // is unknown and the position held (ImuFuser::restart_at_rest).
  bool awaiting_rest = false;
  std::uint32_t rests = 0;  // waits for rest that ended (ImuFuserStats::rests)
  // Since an IMU gap the velocity is the registrations' alone, until a rest
  // confirms it (ImuFuser::velocity_confirmed).
  bool velocity_unconfirmed = false;
  std::uint32_t runaways_at_rest = 0;  // ImuFuserStats::runaways_at_rest
};

using tumble::WeightModel;

// Why the registration thread gave up its local map and started a new one.
enum class TrackingLoss : std::uint8_t {
  None = 0,
  NotRegistered,      // consecutive scans without enough matches
  DisagreesWithImu,   // consecutive registrations far from the IMU-propagated pose
  LidarSilent,        // no scan for longer than daemon.health.lidar_silent_to_lost_s
  UnobservedMap,      // a direction pinned again after an unobserved spell: the map grew on unmeasured poses
  TooFast,            // the fused speed beyond fuser.max_speed_m_s: the velocity ran away
  MovingAtRest,       // the fused speed beyond fuser.max_speed_at_rest_m_s while the IMU was still
};
constexpr std::string_view to_string(TrackingLoss loss) {
  switch (loss) {
    case TrackingLoss::None:
      return "none";
    case TrackingLoss::NotRegistered:
      return "scans not registered (too few matches)";
    case TrackingLoss::DisagreesWithImu:
      return "registrations disagree with the IMU-propagated pose";
    case TrackingLoss::LidarSilent:
      return "lidar silent too long: the IMU alone carried the pose";
    case TrackingLoss::UnobservedMap:
      return "a direction unobserved for a while is pinned again: the map grew on poses not measured along it";
    case TrackingLoss::TooFast:
      return "fused speed beyond fuser.max_speed_m_s: the velocity ran away with registrations that agreed with it";
    case TrackingLoss::MovingAtRest:
      return "moving beyond fuser.max_speed_at_rest_m_s while the IMU was still: the velocity ran away with "
             "registrations that agreed with it";
  }
  return "unknown";
}

// One registered scan, as the registration thread reports it (to the fuser as
// a correction, to LCM as tumble.registration_t, to the trajectory file).
struct RegistrationRecord {
  static constexpr std::size_t kMaxStages = 8;
  double t_s = 0.0;  // the scan's first point
  double t_end_s = 0.0;  // its last point
  std::int64_t scan_index = 0;
  std::array<double, 3> position_m{};
  std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};
  std::array<double, 3> velocity_m_s{};
  std::array<double, 36> covariance{};  // 6x6 row-major over (tx, ty, tz, rx, ry, rz): published_covariance()
  std::int32_t iterations = 0;
  bool registered = false;       // false: the fuser's pose is reported and no correction is made
  bool map_initialised = false;  // the scan that started the map
  bool converged = false;
  ScanCorrection correction;  // scan_correction_of(ScanResult): what the fuser takes when registered
  // ScanResult::jumped: far from the prediction, so neither good nor a velocity measurement.
  bool jumped = false;
  // Tracking was lost and the fuser has not yet found the robot at rest: not
  // registered, no new map yet (core_stages.cpp).
  bool awaiting_rest = false;
  std::array<float, 3> held_translation_w{};  // ScanResult::held_translation_w: unmeasured by this scan
  bool prediction_prior = false;              // ScanResult::prediction_prior
  bool weak_translation_predicted = false;    // ScanResult::weak_translation_predicted
  float inlier_ratio = 0.0f;
  float matched_ratio = 0.0f;      // ICP points with a map match at the last iteration
  float correction_m = 0.0f;       // ICP's pose from the IMU-propagated one, at the scan start
  float correction_deg = 0.0f;
  std::array<float, 3> correction_w_m{};  // ICP's position minus the IMU-propagated one, W axes
  float residual_m = 0.0f;
  float degeneracy = 0.0f;
  // expected_position_error_m() of the covariance; above daemon.health.max_expected_error_m
  // the scan is weakly constrained (not a good scan).
  float expected_error_m = 0.0f;
  float expected_error_icp_m = 0.0f;  // ScanResult::expected_error_icp_m: the fuser's levelling goes by it
  float expected_rotation_error_icp_rad = 0.0f;  // ScanResult::expected_rotation_error_icp_rad: and by this
  WeightModel model = WeightModel::GVTW;
  bool deskew = true;
  std::int32_t points_in = 0;
  std::int32_t points_used = 0;
  std::int32_t map_points = 0;              // in the local map after the scan
  std::int32_t map_points_seen_through = 0;  // removed from the map: the scan's beams passed through them
  float sigma_s_median_m = 0.0f;
  float sigma_s_max_m = 0.0f;
  std::int64_t scan_complete_steady_ns = 0;  // when the scan's last packet was taken (for latency)
  std::uint8_t num_stages = 0;               // names: RegistrationStage::stage_names()
  std::array<float, kMaxStages> stage_ms{};
  std::int32_t resets = 0;              // local maps given up so far (this scan started a new one when it grew)
  TrackingLoss reset_reason = TrackingLoss::None;  // of the newest reset
  // Registered while the velocity was unconfirmed since an IMU gap
  // (TrajectoryRecord::velocity_unconfirmed): the scan may agree with it
  // a car's length off in a scene that repeats.
  bool velocity_unconfirmed = false;
  bool imu_bridged = false;             // no IMU over the scan: de-skewed with a prediction from the registrations
  bool untrusted = false;               // registered, but too far from the IMU-propagated pose: not used
  // The gyro was clipped about the lidar's spin axis during the scan: that rate
  // came from the registrations, which hardly observe it (core_stages.hpp).
  bool spin_rate_unmeasured = false;
  // This scan and the clipped ones registered just before it, since the last lidar gap or new map.
  std::int32_t spin_clipped_scans_in_row = 0;
  // No scan registered on a map yet, and the gyro clipped during the scan: it
  // cannot start the first map (core_stages.cpp), so it is not registered.
  bool map_deferred = false;
  // Its weakest direction, and that of most scans before it, only the noise
  // pins (core/unobserved_direction.hpp): the covariance is widened along it.
  bool direction_unobserved = false;
};

// Registered and used, but its expected error (records' expected_error_m) is
// above the limit: the pose may be wrong along its least constrained direction.
inline bool weakly_constrained(const RegistrationRecord& r, double max_expected_error_m) {
  return r.registered && !(r.expected_error_m <= max_expected_error_m);
}

// The sensors' own time, as the io thread sees the replayed records: at each
// health period boundary t_s, the newest IMU and lidar data before it. The
// registration thread passes it on once every scan that ended before it is
// reported, so the health machine sees the same inputs on every replay.
struct SensorTimeTick {
  double t_s = 0.0;
  double newest_imu_s = -1.0;    // < 0: none yet
  double newest_lidar_s = -1.0;
  std::uint64_t lidar_items = 0;   // lidar ring pushes before this tick
  std::uint64_t scan_reports = 0;  // scan reports pushed before this tick (set by the registration thread)
  double foreign_lidar_rate_hz = 0.0;  // PipelineCounters::lidar_foreign_rate_hz at this tick
};

}  // namespace tumble::daemon
