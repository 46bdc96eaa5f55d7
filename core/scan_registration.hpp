// The registration half of the odometry (docs/method.md §2–5): one scan and the
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
#include <span>

#include "core/icp.hpp"
#include "core/imu_fuser.hpp"
#include "core/local_map.hpp"
#include "core/normals.hpp"
#include "core/parallel_runner.hpp"
#include "core/point_cloud.hpp"
#include "core/point_weights.hpp"
#include "core/position_uncertainty.hpp"
#include "core/registration_confidence.hpp"
#include "core/scan_line_normals.hpp"
#include "core/seen_through.hpp"
#include "core/trajectory.hpp"
#include "core/types.hpp"
#include "core/unobserved_direction.hpp"
#include "core/voxel_grid.hpp"

namespace tumble {

struct OdometryParams {
  bool deskew = true;
  bool wait_for_imu = true;
  std::size_t max_pending_scans = 4;  // scans waiting for IMU coverage
  std::size_t min_scan_points = 100;  // fewer after down-sampling: the scan is skipped
  double voxel_size_m = 0.05;
  // The points that enter ICP (KISS-ICP's double down-sampling): of the
  // voxel_size_m cloud, the one nearest the centre of each cell of this size.
  // The map still receives the whole voxel_size_m cloud, and the normals and
  // σ's of the registered points are fitted from that whole cloud. 0 (or
  // <= voxel_size_m): register every point, as the paper does.
  // Why 0.2 m (ours, not the paper's): ICP and reading-normal cost are linear
  // in the registered points (about a quarter of an RS-16 scan's points
  // enter ICP; docs/decisions/map-spacing.md).
  double registration_voxel_size_m = 0.2;
  NormalParams reading_normals{.k = 15};
  // Where the reading's neighbourhoods come from: the k nearest points
  // (docs/method.md §4; k and the line retry in reading_normals), or a window
  // of the scan's rings (ScanLineNormals; reading_normals' limits still
  // apply). Ours: the window makes the normals 4-5x faster for about the
  // same error (docs/decisions/reading-normals.md). tumbled defaults to the
  // window (registration.reading_normals); the core's default stays the method's.
  ReadingNormalSource reading_normal_source = ReadingNormalSource::kNearest;
  ScanLineWindow scan_line_window;
  // The map: radius_m 50, min_point_distance_m 0.05, max_sigma_s_m 1,
  // max_points_per_voxel 100, voxel_size_m 0.5, normals (k 20 and the validity limits).
  LocalMapParams map;
  // Map points that a registered scan's beams see through leave the map
  // (people, the rope puller, doors). Only scans de-skewed with a
  // measured trajectory (the beams' geometry is known only then) and
  // registered within seen_through.max_expected_error_m.
  SeenThroughParams seen_through;
  // A direction weak in most recent scans is published as unobserved
  // (unobserved_direction.hpp), with a wide covariance along it.
  UnobservedDirectionParams unobserved;
  // The published covariance: κ, the floor, the normals' noise (registration_confidence.hpp).
  RegistrationConfidenceParams confidence;
  // The prediction as ICP's prior and in the published covariance
  // (position_uncertainty.hpp); off by default (the paper's ICP).
  PositionUncertaintyParams position;
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
  double registration_s = 0;  // the whole ICP stage, the two below included
  double icp_matching_s = 0;  // in ICP: finding, checking and trimming correspondences, and the
                              // normals of map points matched for the first time
  double icp_solve_s = 0;     // in ICP: building and solving the normal equations
  double fuser_correction_s = 0;
  double seen_through_s = 0;  // removing the map points the scan's beams passed through
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
  // Per W axis, the ICP covariance's (the scan alone, without the prior),
  // calibrated by κ² (registration_confidence.hpp): ScanCorrection::
  // position_var_w_m2. Zero for the scan that starts a map.
  Eigen::Vector3d position_var_w_m2 = Eigen::Vector3d::Zero();
  // Registered far from the prediction (PositionUncertaintyParams::jump_sigmas):
  // the pose is used, the map is left as it was, the velocity is not
  // measured across it (ScanCorrection::jumped), and it is not good.
  bool jumped = false;
  // The covariance to publish (registration_confidence.hpp: the normals'
  // noise discounted, calibrated, widened along an unobserved direction) and
  // its expected error; set once ICP has run (the first scan of a map: the
  // floor alone).
  Matrix6d covariance_published = published_covariance(Matrix6d::Identity());
  double expected_error_m = expected_position_error_m(covariance_published);
  // UnobservedDirection: a direction the recent scans have not pinned, from
  // a spell's start until the window holds no weak scan (since_spell()).
  bool direction_unobserved = false;
  // This scan ended an unobserved spell: the map took points meanwhile at
  // poses nothing measured along that direction. The daemon starts a new
  // map (reset_map()); the core's Odometry keeps it.
  bool unobserved_spell_ended = false;
  // The expected error of the ICP's covariance as it is, calibrated: what the
  // seen-through gate and the fuser's levelling go by (their thresholds were
  // chosen on it), the levelling also by the rotation figure below.
  double expected_error_icp_m = expected_error_m;
  // The same covariance's expected attitude error: a corridor's scans pin the
  // attitude while their position error is large, and levelling needs only
  // the attitude (ImuFuserParams::levelling_max_rotation_error_rad).
  double expected_rotation_error_icp_rad = expected_rotation_error_rad(covariance_published);
  bool map_initialised = false;  // the first scan: inserted at the fuser's pose, not registered
  bool registered = false;       // false: too few matches (or rejected), the fuser's pose is kept
  bool rejected = false;         // matched, but beyond ScanConditions' limits from the prediction: not used
  // ICP's pose vs the trajectory's, at the scan start: position (W axes) and rotation angle.
  Eigen::Vector3d correction_w = Eigen::Vector3d::Zero();
  double rotation_from_prediction_rad = 0;
  bool converged = false;
  int iterations = 0;
  double inlier_ratio = 0;
  double matched_ratio = 0;  // IcpResult::matched_ratio
  double residual_rms_m = 0;
  Degeneracy degeneracy;
  Eigen::Vector3d held_translation_w = Eigen::Vector3d::Zero();  // IcpResult::held_translation_w
  bool prediction_prior = false;  // ICP had the prediction as a prior (PositionUncertainty)
  // With the prior, a weak scan whose weakest direction is mostly a
  // translation: the prediction's covariance, not the scan's, is published
  // along it (the expected error then says how well it is known).
  bool weak_translation_predicted = false;
  std::size_t points_in = 0;
  std::size_t points_downsampled = 0;
  std::size_t points_registered = 0;  // that entered ICP (registration_voxel_size_m)
  std::size_t map_points = 0;  // after the update
  std::size_t map_points_seen_through = 0;  // removed from the map by this scan's beams
  // rejected_too_close also counts the points ruled out before their σ's
  // were computed (a map point within the minimum distance); rejected_sigma
  // only the others.
  MapInsertStats map_insert;
  StageTimings timings;
};

// What the fuser takes from a registered scan (ImuFuser::correct_with_registered_pose).
ScanCorrection scan_correction_of(const ScanResult& result);

enum class ScanOutcome {
  Registered,  // result filled (including map initialisation and failed matches)
  TooSmall,    // fewer than min_scan_points after down-sampling
  OutOfOrder,  // starts at or before the previous scan
};

// When the sensors were not all there (the daemon): how to take one scan.
struct ScanConditions {
  bool deskew = true;
  // false: the trajectory is only a prediction (no IMU over the scan), so the
  // points get the no-de-skew σ's (docs/method.md §3) even when de-skewed with it.
  bool trajectory_measured = true;
  // The registered pose is accepted only this close to the trajectory's (<= 0:
  // any); otherwise the result is `rejected`, not `registered`, and the map
  // is left as it was.
  double max_translation_m = 0;
  double max_rotation_rad = 0;
};

class ScanRegistration {
 public:
  using Clock = std::function<double()>;

  // Throws std::invalid_argument naming the inconsistent parameter. The
  // per-point loops (normals, ICP matching, the map's new normals) run on
  // `runner`'s threads; the result is the same for any runner.
  explicit ScanRegistration(const OdometryParams& params, Clock clock = {}, ParallelRunner& runner = serial_runner());

  // `trajectory` should cover the scan (queries beyond its ends extrapolate).
  // result.v_w and timings.fuser_correction_s are left for the caller.
  ScanOutcome process(const Scan& scan, const Trajectory& trajectory, ScanResult& result);
  ScanOutcome process(const Scan& scan, const Trajectory& trajectory, ScanResult& result,
                      const ScanConditions& conditions);

  // Gives up the local map: the next scan starts a new one at the trajectory's pose.
  void reset_map();

  // The last processed scan's registered points (the down-sampled cloud, or
  // its registration_voxel_size_m subset) in the lidar frame at its first
  // point, with normals, σ's and weights.
  const PointCloud& reading() const { return registered_; }
  const LocalMap& map() const { return map_; }

 private:
  // One scan's facts that its stages share.
  struct ScanInputs {
    const Trajectory& trajectory;
    const ScanConditions& conditions;
    double t_start_s;
    double t_last_s;  // the down-sampled scan's latest point
  };

  double now() const { return clock_ ? clock_() : 0.0; }
  // Adds the time since the last lap to `stage_s`: stages run in pieces (the
  // normals and σ's of the map's new points come after ICP), and the pieces
  // sum to the total.
  void lap(double& stage_s);

  // The stages, in the order process() runs them.
  void deskew(const Scan& scan, const Trajectory& trajectory, bool along_trajectory);
  void downsample(ScanResult& result);
  void fit_registered_normals(const Scan& scan);
  void weigh_registered(const ScanInputs& in);
  void align_to_map(const ScanInputs& in, const Eigen::Isometry3d& predicted, const Eigen::Vector3d& velocity_var_w,
                    ScanResult& result);
  void estimate_uncertainty(const ScanInputs& in, const Eigen::Vector3d& velocity_var_w, ScanResult& result);
  void remove_seen_through(const ScanInputs& in, ScanResult& result);
  void add_to_map(const ScanInputs& in, ScanResult& result);

  bool weighs_whole_scan() const;
  bool normals_from_scan_lines() const;
  void fit_normals(std::span<const std::uint32_t> indices);  // of reading_, each once per scan
  void weigh(const ScanInputs& in, PointCloud& cloud);
  void gather(std::span<const std::uint32_t> indices, PointCloud& out) const;  // from reading_

  OdometryParams params_;
  Clock clock_;
  ParallelRunner& runner_;
  VoxelDownsampler downsampler_;
  NormalEstimator normals_;
  ScanLineNormals line_normals_;
  std::vector<double> ring_elevations_rad_;
  PointWeightWorkspace weight_workspace_;
  Icp icp_;
  LocalMap map_;
  SeenThroughRemover seen_through_;
  UnobservedDirection unobserved_direction_;
  PositionUncertainty position_uncertainty_;
  std::vector<MapBeam> beams_;
  std::size_t seen_through_scans_ = 0;  // scans that removed seen-through points: which beams are next
  std::vector<Eigen::Vector3d> returns_w_;  // the down-sampled scan in the world frame
  double last_scan_start_s_ = -1e300;
  VoxelDownsampler registration_selector_;
  PointCloud raw_;
  PointCloud reading_;     // the down-sampled scan; normals only where computed (normal_done_)
  PointCloud registered_;  // the points ICP registers
  PointCloud map_candidates_;  // the points the map may take
  std::vector<std::uint8_t> normal_done_;
  std::vector<std::uint32_t> registered_indices_;
  std::vector<std::uint32_t> candidate_indices_;
  std::vector<std::uint32_t> normals_todo_;
  std::vector<std::uint32_t> all_indices_;
  double lap_mark_ = 0;  // the clock at the last lap
};

}  // namespace tumble
