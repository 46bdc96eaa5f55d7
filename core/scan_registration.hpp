// The registration half of the odometry (algorithm.md §2–5): one scan and the
// fuser's trajectory over it in, the registered pose out, the local map
// updated. De-skew, down-sample, normals, weights, weighted ICP, map update.
// Odometry runs it inside the IMU loop; tumbled runs it on its registration
// thread with a snapshot of the trajectory, and hands the result to the fuser
// on another thread (which is why the fuser correction is not in here).
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <functional>

#include "core/icp.hpp"
#include "core/imu_fuser.hpp"
#include "core/local_map.hpp"
#include "core/normals.hpp"
#include "core/point_cloud.hpp"
#include "core/point_weights.hpp"
#include "core/trajectory.hpp"
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

// Throws std::invalid_argument naming the inconsistent parameter.
void check_odometry_params(const OdometryParams& params);

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
  double position_sigma_m = 0;   // what the fuser's velocity filter is told
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

enum class ScanOutcome {
  Registered,  // result filled (including map initialisation and failed matches)
  TooSmall,    // fewer than min_scan_points after down-sampling
  OutOfOrder,  // starts at or before the previous scan
};

class ScanRegistration {
 public:
  using Clock = std::function<double()>;

  // Throws std::invalid_argument naming the inconsistent parameter.
  explicit ScanRegistration(const OdometryParams& params, Clock clock = {});

  // `trajectory` should cover the scan (queries beyond its ends extrapolate).
  // result.v_w and timings.fuser_correction_s are left for the caller.
  ScanOutcome process(const Scan& scan, const Trajectory& trajectory, ScanResult& result);

  // The last processed scan's down-sampled points in the lidar frame at its
  // first point, with normals, σ's and weights.
  const PointCloud& reading() const { return reading_; }
  const LocalMap& map() const { return map_; }
  // Forget the map and the scan order (re-initialisation after being lost).
  void reset();

 private:
  double now() const { return clock_ ? clock_() : 0.0; }

  OdometryParams params_;
  Clock clock_;
  VoxelDownsampler downsampler_;
  NormalEstimator normals_;
  PointWeightWorkspace weight_workspace_;
  Icp icp_;
  LocalMap map_;
  double last_scan_start_s_ = -1e300;
  PointCloud raw_;
  PointCloud reading_;
};

}  // namespace tumble
