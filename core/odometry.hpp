// The lidar-inertial odometry pipeline (architecture.md, algorithm.md): IMU
// samples drive the fuser; each lidar scan is de-skewed with the fuser's
// trajectory, down-sampled, given normals and weights, registered to the
// rolling local map, fed back to the fuser and inserted into the map.
//
// Scheduling: with wait_for_imu (default) a scan is held until the fuser's
// trajectory reaches the scan's last point time (de-skewing and the weight
// models need the motion over the whole scan); it is then processed inside the
// add_imu() call that covered it. Held scans are kept in a small fixed queue;
// when it is full the oldest is dropped and counted. Without wait_for_imu a scan
// is processed inside add_scan() at once, and the trajectory past its last IMU
// sample is extrapolated with the last velocity and body rate.
// Scans arriving before the fuser has initialised (its static window) are
// dropped and counted; the first scan after that initialises the map at the
// fuser's pose and is not registered.
//
// Core has no clock: per-stage timings come from the clock the caller injects
// (seconds, any monotonic origin); without one they are not measured.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/icp.hpp"
#include "core/imu_fuser.hpp"
#include "core/local_map.hpp"
#include "core/normals.hpp"
#include "core/point_cloud.hpp"
#include "core/point_weights.hpp"
#include "core/types.hpp"
#include "core/voxel_grid.hpp"

namespace tumble {

struct OdometryParams {
  bool deskew = true;
  bool wait_for_imu = true;
  std::size_t max_pending_scans = 4;  // scans waiting for IMU coverage
  std::size_t min_scan_points = 100;  // fewer after down-sampling: the scan is skipped
  double voxel_size_m = 0.05;
  NormalParams reading_normals{.k = 15};
  // The map: radius_m 50, min_point_distance_m 0.05, max_sigma_s_m 1,
  // max_points_per_voxel 40, voxel_size_m 0.25, normals (k 20 and the validity limits).
  LocalMapParams map;
  // Registration: max_match_distance_m 1, match_k 1, FRMSD 0.5/0.7/2.35,
  // max_iterations 40, convergence. `icp.weighting` is set from the weight
  // model (SAW: the point's weight; the others: inverse variance).
  IcpParams icp;
  // Weight model (weights.model: NM, TW, VTW, GVTW, SAW), σ_n, model constants.
  // weights.map_max_sigma_m must equal map.max_sigma_s_m (one cut, two owners).
  PointWeightParams weights;
  // Extrinsic, initialisation, Madgwick, velocity filter; speed-uncertainty
  // models are fuser.speed_uncertainty.
  ImuFuserParams fuser;
  // The registration's position sigma handed to the fuser's velocity filter is
  // at least this: the ICP covariance ignores correlated matches and map error.
  double min_position_sigma_m = 0.01;
};

// Seconds spent per stage of one scan, from the injected clock.
struct StageTimings {
  bool measured = false;  // false when no clock was given
  double deskew_s = 0;
  double downsample_s = 0;
  double normals_s = 0;
  double weights_s = 0;
  double registration_s = 0;
  double fuser_correction_s = 0;
  double map_update_s = 0;
  double total_s = 0;
};

struct ScanResult {
  std::uint64_t scan_index = 0;
  double t_scan_start_s = 0;  // time of the scan's first point: the pose's time
  double t_scan_end_s = 0;
  Eigen::Isometry3d T_wl = Eigen::Isometry3d::Identity();  // registered lidar pose at t_scan_start_s
  Eigen::Vector3d v_w = Eigen::Vector3d::Zero();           // fused lidar velocity at t_scan_start_s
  Matrix6d covariance = Matrix6d::Identity();              // IcpResult::covariance
  bool map_initialised = false;  // the first scan: inserted at the fuser's pose, not registered
  bool registered = false;       // false: too few matches, the fuser's pose is kept
  bool converged = false;
  int iterations = 0;
  double inlier_ratio = 0;
  double residual_rms_m = 0;
  Degeneracy degeneracy;
  std::size_t points_in = 0;
  std::size_t points_downsampled = 0;
  std::size_t map_points = 0;  // after the update
  MapInsertStats map_insert;
  StageTimings timings;
};

struct OdometryStats {
  std::uint64_t scans_received = 0;
  std::uint64_t scans_processed = 0;
  std::uint64_t scans_before_init = 0;       // dropped: the fuser was not initialised
  std::uint64_t scans_dropped_pending = 0;   // dropped: the wait queue was full
  std::uint64_t scans_too_small = 0;         // fewer than min_scan_points
  std::uint64_t scans_out_of_order = 0;      // starting before the previous scan: dropped
  std::uint64_t registrations_failed = 0;    // too few matches
  std::uint64_t registrations_degenerate = 0;
};

class Odometry {
 public:
  using Clock = std::function<double()>;
  using ScanCallback = std::function<void(const ScanResult&)>;
  using PoseCallback = std::function<void(const TrajectorySample&)>;

  // Throws std::invalid_argument naming the inconsistent parameter.
  explicit Odometry(const OdometryParams& params, Clock clock = {});

  // Called with every scan result, inside add_imu()/add_scan().
  void set_scan_callback(ScanCallback callback) { on_scan_ = std::move(callback); }
  // Called after every IMU sample once the fuser is initialised, with the
  // newest fused lidar state (the high-rate pose).
  void set_pose_callback(PoseCallback callback) { on_pose_ = std::move(callback); }

  // Both return how many scans were processed during the call.
  std::size_t add_imu(const ImuSample& sample);
  std::size_t add_scan(const Scan& scan);

  const std::optional<ScanResult>& last_result() const { return last_result_; }
  const ImuFuser& fuser() const { return fuser_; }
  const LocalMap& map() const { return map_; }
  const OdometryStats& stats() const { return stats_; }
  const OdometryParams& params() const { return params_; }

 private:
  bool covered_by_imu(const Scan& scan) const;
  std::size_t process_ready_scans();
  bool process(const Scan& scan);  // false: dropped (counted)
  Eigen::Vector3d velocity_at(double t_s) const;
  double now() const { return clock_ ? clock_() : 0.0; }

  OdometryParams params_;
  Clock clock_;
  ScanCallback on_scan_;
  PoseCallback on_pose_;

  ImuFuser fuser_;
  VoxelDownsampler downsampler_;
  NormalEstimator normals_;
  PointWeightWorkspace weight_workspace_;
  Icp icp_;
  LocalMap map_;

  std::vector<Scan> pending_;  // ring of max_pending_scans, storage reused
  std::size_t pending_head_ = 0;
  std::size_t pending_count_ = 0;
  double last_scan_start_s_ = -1e300;

  PointCloud raw_;
  PointCloud reading_;
  std::optional<ScanResult> last_result_;
  OdometryStats stats_;
};

}  // namespace tumble
