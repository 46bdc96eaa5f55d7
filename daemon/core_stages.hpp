// The core's odometry split across the daemon's two compute threads
// (seams.hpp): ImuFuser on the fuser thread, scan assembly and
// ScanRegistration on the registration thread. The registration thread sees
// the trajectory only as the TrajectoryRecords the fuser published; it
// rebuilds a core Trajectory from the window around each scan.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/imu_fuser.hpp"
#include "core/scan_registration.hpp"
#include "core/trajectory.hpp"
#include "daemon/config.hpp"
#include "daemon/rate_limited_log.hpp"
#include "daemon/seams.hpp"
#include "daemon/worker_pool.hpp"
#include "drivers/rs16/decoder_stats.hpp"
#include "drivers/rs16/scan_assembler.hpp"

namespace tumble::daemon {

TrajectoryRecord to_record(const TrajectorySample& sample);
TrajectorySample to_sample(const TrajectoryRecord& record);

// The fuser thread's stage. Records carry the registration's reset count and
// whether the fuser re-anchored on registered poses after an IMU gap and has
// not been corrected since (odometry_t FLAG_IMU_BRIDGED).
class CoreFuserStage : public FuserStage {
 public:
  explicit CoreFuserStage(const OdometryParams& params);

  bool add_imu(const ImuSample& sample, TrajectoryRecord& out) override;
  void add_correction(const RegistrationRecord& registration,
                      const std::function<void(const TrajectoryRecord&)>& republish) override;

 private:
  TrajectoryRecord record_of(const TrajectorySample& sample) const;

  OdometryParams params_;
  ImuFuser fuser_;
  double newest_published_s_ = -1e300;
  std::int32_t resets_ = 0;
  std::uint64_t reanchors_corrected_ = 0;  // the fuser's re-anchor count at the newest correction
  std::array<double, 3> position_var_m2_{};  // of the newest registered pose (until one: min_position_sigma_m²)
};

// The registration thread's stage. Beyond registering:
// - IMU gap: when the fused trajectory has a hole longer than the fuser's
//   max_imu_gap_s over the scan (the fuser counts those as gaps too), the scan is registered against a
//   prediction from the last two registered poses (constant velocity and body
//   rate), not de-skewed, with the no-de-skew σ's (`imu_bridged`).
// - Lidar gap: for kScansCheckedAfterLidarGap scans after a gap of more than
//   kLidarGapToCheck_s, a registration farther from the IMU-propagated pose
//   than that pose can be wrong is `untrusted`: not registered, not in the
//   map, not sent to the fuser.
// - Lidar silent for longer than lidar_silent_to_reset_s: the IMU alone has
//   carried the pose too far for a registration against the old map to be
//   trusted (after a 3 s restart mid-tumble such registrations were wrong by
//   metres and published as good). The
//   next scan starts a new local map at the fuser's pose (a reset, counted,
//   with its reason); the health machine reported lost meanwhile.
// - Lost: kScansToReset scans in a row not registered or untrusted, and the
//   stage gives up its local map (a reset, counted, with its reason); the next
//   scan starts a new one at the fuser's pose, which continues the last one
//   published.
// - Lost for a reason the fuser's velocity may cause (scans not registered,
//   or disagreeing with the IMU): the fuser drops its velocity and waits for
//   the robot to rest (ImuFuser::restart_at_rest); until then scans are not
//   registered (`awaiting_rest`), and the new map starts after the rest.
// - Gyro clipped about the lidar's spin axis during the scan: the scan is
//   registered as usual (the fuser takes that rate from the registrations,
//   core/imu_fuser.hpp 6), but flagged `spin_rate_unmeasured`: that
//   rotation is the registration's alone. The health machine reports
//   degraded for the first scans of such a spell, and for one that matched
//   little of the map (daemon.health.spin_clipped_scans_to_settle,
//   min_matched_ratio_spin_clipped; scan_verdict.cpp).

class CoreRegistrationStage : public RegistrationStage {
 public:
  // threads: the registration thread plus threads − 1 helpers (WorkerPool),
  // each starting with on_helper_start(helper number).
  // lidar_silent_to_reset_s: daemon.health.lidar_silent_to_lost_s.
  CoreRegistrationStage(const OdometryParams& params, const rs16::ScanAssemblerConfig& scans,
                        double lidar_silent_to_reset_s = HealthConfig{}.lidar_silent_to_lost_s, std::size_t threads = 1,
                        std::function<void(std::size_t)> on_helper_start = {});

  std::vector<std::string> stage_names() const override;
  bool add_points(const PointBlock& block) override;
  TimeSpan held_scan_span() const override;
  void register_held_scan(std::span<const TrajectoryRecord> trajectory, RegistrationRecord& out,
                          tumble::scan_t* viewer_scan) override;
  void fill_viewer_map(tumble::map_t& map) const override;
  void discard_held_scan() override;
  void report(PipelineCounters& counters) const override;

 private:
  // velocity_w_m_s: the fused velocity at the scan's start.
  void fill_record(const ScanResult& result, const Eigen::Vector3d& velocity_w_m_s, RegistrationRecord& out);
  bool predict_from_registrations(double t_start_s, double t_end_s);
  void keep_track(const ScanResult& result);
  void reset_map(TrackingLoss reason);
  void forget_poses_and_reset_map(TrackingLoss reason);

  struct Pose {
    double t_s = 0.0;
    Eigen::Isometry3d T_wl = Eigen::Isometry3d::Identity();
  };
  void warn_of_packet_faults(const rs16::DecoderStats& before, double now_s);

  OdometryParams params_;
  double min_scan_coverage_;
  rs16::ScanAssembler assembler_;
  rs16::DecoderStats assembly_stats_;
  RateLimitedLog fault_log_{1, 10.0};  // duplicated, late and short scans, once per period each
  WorkerPool pool_;  // before registration_, which keeps a reference
  ScanRegistration registration_;
  Trajectory trajectory_;
  Scan held_;
  bool holding_ = false;
  ScanResult result_;
  std::vector<float> sigma_scratch_;
  Trajectory prediction_;             // for a scan the IMU did not cover
  std::optional<Pose> newest_pose_;   // the two newest registered (trusted) poses
  std::optional<Pose> previous_pose_;
  double lidar_silent_to_reset_s_;
  double previous_scan_start_s_ = -1e300;
  double previous_scan_end_s_ = -1e300;
  std::int32_t spin_clipped_scans_in_row_ = 0;
  int scans_to_check_ = 0;            // after a lidar gap
  int scans_lost_in_a_row_ = 0;
  // After a lidar silence the velocity is the IMU's dead reckoning, which
  // the new map's registrations measure: the speed limit does not judge that map.
  bool speed_limit_applies_ = true;
  bool registered_on_a_map_ = false;  // since then the fuser has a lidar rate for clipped axes
  std::int32_t resets_ = 0;
  TrackingLoss reset_reason_ = TrackingLoss::None;
  // Set by a loss of track that restarts the fuser at rest: the fuser's rest
  // count then. No new map until the trajectory shows a later rest.
  std::optional<std::uint32_t> rests_before_loss_;
  std::uint32_t runaways_at_rest_seen_ = 0;  // TrajectoryRecord::runaways_at_rest at the last scan
};

}  // namespace tumble::daemon
