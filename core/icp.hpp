// Weighted point-to-plane ICP against the local map (docs/method.md §3-4):
// Gauss-Newton on SE(3), FRMSD (variable trimmed distance) outlier rejection,
// a convergence checker, and a degeneracy report with every result.
//
// Neighbour reuse (speed, exact): each search keeps a few neighbours more
// than match_k, from a radius a margin beyond max_match_distance_m, so it knows
// every map point within some radius D of the query. A reading point that has
// since moved by δ (bounded from the pose change: |Δt| + angle(ΔR)·range) can
// only have new neighbours among those it kept while its k-th nearest of them
// stays closer than D − δ; then they are re-ranked at the new pose and the
// search is skipped. Once the increments are millimetres, most points skip it.
// The matches are the same as a fresh search's (up to ties in distance).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "core/grid_search.hpp"
#include "core/local_map.hpp"
#include "core/parallel_runner.hpp"
#include "core/point_cloud.hpp"

namespace tumble {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

enum class ConvergenceCriterion {
  kAveragedIncrement,  // the authors' checker: mean of the last `window` increments below (1e-3 rad, 1e-2 m)
  kIncrementBelow,     // the last increment below (1e-4 rad, 1e-4 m)
};

enum class MatchWeighting {
  kInverseVariance,  // 1 / (σn_read² + σs_read² + σn_ref² + σs_ref²)  (NM, TW, VTW, GVTW)
  kPointWeight,      // the reading point's own weight (SAW gives the weight itself)
};

enum class TrimDistance {
  kPointToPlane,  // the squared point-to-plane residual, which the cost sees
  kMatch,         // the squared matching (point-to-point) distance: libpointmatcher's input
};

struct IcpParams {
  double max_match_distance_m = 1.0;
  int match_k = 1;  // map neighbours matched per reading point (the authors used 8)
  double frmsd_r_min = 0.5;
  double frmsd_r_max = 0.7;
  double frmsd_lambda = 2.35;
  TrimDistance trim_distance = TrimDistance::kMatch;
  // A match whose reading normal (when valid) and map normal differ by more
  // than this is dropped (libpointmatcher's SurfaceNormalOutlierFilter): it
  // pairs different surfaces, or a map normal blended across an edge. The test
  // starts once the estimate has converged without it (before, its rotation
  // error could exceed the angle), and iterating goes on until the estimate
  // converges again with it. >= 90: off.
  double max_normal_angle_deg = 10.0;
  int max_iterations = 40;
  ConvergenceCriterion convergence = ConvergenceCriterion::kAveragedIncrement;
  double averaged_rotation_rad = 1e-3;
  double averaged_translation_m = 1e-2;
  int averaged_window = 2;
  double increment_rotation_rad = 1e-4;
  double increment_translation_m = 1e-4;
  MatchWeighting weighting = MatchWeighting::kInverseVariance;
  // Degenerate when the smallest eigenvalue of the (unit-balanced) normal
  // matrix is below this fraction of the largest.
  double degeneracy_ratio = 1e-3;
  // Ours: a step along the normal matrix's weakest direction, when
  // its eigenvalue is below this share of the sum of weights
  // (Degeneracy::min_eigenvalue) and the direction is mostly a translation,
  // follows the noise in the normals, not the geometry. Such an iteration
  // solves the rest with the translation along it held (the initial pose's,
  // the IMU's prediction, carries it), and the result says so. Where the
  // pose slid along a lane it was the step that slid it
  // (docs/decisions/weak-scan-hold.md). The rotation stays solved: holding
  // the whole weakest direction, which mixes the translation with a pitch,
  // broke two cage runs. 0: never (the paper's ICP).
  double hold_weak_translation_share = 0.0;
  // Re-rank a point's kept neighbours instead of searching again when that
  // provably gives the same matches (see the top of this file). false: search
  // every point at every iteration (same result, for checking).
  bool reuse_neighbours = true;
};

// The weakest direction of the last Gauss-Newton normal matrix. The rotation
// part is scaled by length_scale_m (RMS distance of the matched points from the
// sensor), so all six coordinates are metres of point displacement and
// eigenvalues compare across rotation and translation.
struct Degeneracy {
  double min_eigenvalue = 0;       // of the scaled matrix divided by the sum of weights: in [0, 1]
  Vector6d direction = Vector6d::Zero();  // unit, (tx, ty, tz, L·rx, L·ry, L·rz)
  double condition_number = 0;     // largest / smallest eigenvalue (inf when singular)
  double length_scale_m = 1;
  bool degenerate = true;          // also true when there were too few matches
  // s²/W: the covariance's eigenvalue along a direction whose eigenvalue is a
  // share x of the weights is this / x (registration_confidence.hpp).
  double residual_variance_per_weight = 0;
};

// Whether a unit direction of the normal matrix (scaled coordinates, like
// Degeneracy::direction) is mostly a translation: its translation part's
// norm above 0.5. Such a weakest direction is held
// (IcpParams::hold_weak_translation_share), or taken from the prediction
// (position_uncertainty.hpp).
inline bool mostly_translation(const Vector6d& direction) { return direction.head<3>().norm() > 0.5; }

struct IcpResult {
  Eigen::Isometry3d T_wl = Eigen::Isometry3d::Identity();
  int iterations = 0;
  bool converged = false;
  std::size_t matches_considered = 0;  // within max distance, valid and agreeing normals, positive weight
  std::size_t matches_kept = 0;        // after FRMSD
  double inlier_ratio = 0;             // kept / considered: FRMSD's trim fraction, in [frmsd_r_min, frmsd_r_max]
  double matched_ratio = 0;            // reading points with a match in the last matching / reading points
  double residual_rms_m = 0;           // weighted RMS of the point-to-plane residuals kept
  // Of the left perturbation (tx, ty, tz, rx, ry, rz) of T_wl: translation in W,
  // rotation about the sensor origin in W axes; s²·H⁻¹ with s² the weighted
  // residual variance. Correlated matches make it optimistic.
  Matrix6d covariance = Matrix6d::Identity();
  Degeneracy degeneracy;
  // Unit, W axes: the translation the last iteration held
  // (IcpParams::hold_weak_translation_share); zero when it held none.
  Eigen::Vector3d held_translation_w = Eigen::Vector3d::Zero();
  std::size_t neighbour_searches = 0;  // map searches made (the rest were re-ranked from the last search)
  // From the clock given to Icp (0 without one): finding, checking and
  // trimming correspondences vs building and solving the normal equations.
  double matching_s = 0;
  double solve_s = 0;
};

// One ICP iteration's weighted point-to-plane normal equations over the kept
// matches, in the scaled coordinates (t, L·ω): H = Σ w·J·Jᵀ, g = Σ w·r·J.
struct NormalEquations {
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  double weight_sum = 0;
  double residual_variance = 0;  // s²: the weighted squared residuals over the degrees of freedom
  double length_scale = 1;       // L (m)
};

struct FrmsdTrim {
  double ratio = 0;             // kept / n
  std::size_t kept = 0;         // the kept smallest values
  double threshold_sq = 0;      // largest kept squared distance (keep d² <= it)
};

// Phillips' FRMSD overlap choice (libpointmatcher VarTrimmedDistOutlierFilter):
// the k in [r_min·n, r_max·n] minimising sqrt(mean of the k smallest d²)/(k/n)^λ.
// scratch: caller's buffer, reused.
FrmsdTrim frmsd_trim(std::span<const double> squared_distances, double r_min, double r_max, double lambda,
                     std::vector<double>& scratch);

class Icp {
 public:
  using Clock = std::function<double()>;  // seconds

  // Matching (searches and checks) runs on `runner`'s threads.
  explicit Icp(const IcpParams& params = {}, Clock clock = {}, ParallelRunner& runner = serial_runner());

  // Registers `reading` (frame L, with sigmas or weights) to `map`, starting
  // from initial_T_wl. Allocation-free once its buffers have grown.
  // prior_information_w (W axes): the inverse covariance of initial_T_wl's
  // translation, in the units of IcpResult::covariance (the caller's
  // calibration of that covariance applied); each step then minimises the
  // residuals plus that prior, so a direction the scan hardly pins stays
  // near the prediction instead of following the normals' noise. Zero: no
  // prior (the paper's ICP). IcpResult::covariance stays the scan's own.
  IcpResult align(const PointCloud& reading, const LocalMap& map, const Eigen::Isometry3d& initial_T_wl,
                  const Eigen::Matrix3d& prior_information_w = Eigen::Matrix3d::Zero());

  const IcpParams& params() const { return params_; }

 private:
  struct Match {
    Eigen::Vector3d p_w;       // reading point, transformed
    Eigen::Vector3d q_w;       // map point
    Eigen::Vector3d normal_w;  // map normal
    double distance_sq;  // what FRMSD ranks (TrimDistance)
    double weight;
  };
  // What matching needs of a map point, copied at search time so that the
  // iterations that reuse a search read it in order instead of from the map.
  // The normal is read from the map only once the point is a match (most
  // kept neighbours never are, and the map fits a normal on its first read).
  struct KeptNeighbour {
    Eigen::Vector3d p_w;
    Eigen::Vector3d normal_w;
    double variance;  // σn² + σs²
    std::uint32_t map_index;
    bool normal_read;
    bool normal_valid;
  };
  struct RankedNeighbour {
    double distance_sq;
    KeptNeighbour* neighbour;
  };
  // The neighbours reading point i kept from its last search (at the pose of
  // iteration searched_at_[i]): kept_count_[i] of them from kept_[i·capacity],
  // and every map point within clear_radius_m_[i] of the query is among them.
  struct SearchPose {
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
  };
  // A worker's scratch for one point at a time.
  struct WorkerScratch {
    std::vector<Neighbour> neighbours;    // one search's results
    std::vector<RankedNeighbour> ranked;  // the current point's neighbours, nearest first
    std::vector<Neighbour> fit_neighbours;  // a map normal's neighbourhood (LocalMap::fitted_point)
    MapPoint own_fit;                       // LocalMap::fitted_point's, when another worker fits the point
    std::size_t searches = 0;
  };
  // What one iteration's data association needs of the current estimate.
  struct MatchContext {
    const Eigen::Matrix3d& R;
    const Eigen::Vector3d& t;
    int iteration;
    double min_normal_cos;  // 0: no normal test
  };
  // Writes reading point i's matches (at most match_k) to out; returns how many.
  std::size_t match_point(std::size_t i, const PointCloud& reading, const LocalMap& map, const MatchContext& context,
                          WorkerScratch& scratch, Match* out);
  // Fills scratch.ranked with point i's neighbours at p_w (moved at most
  // displacement_m since its last search); returns how many are matches.
  std::size_t neighbours_of(std::size_t i, const Eigen::Vector3d& p_w, int iteration, const LocalMap& map,
                            double displacement_m, WorkerScratch& scratch);
  // The matches FRMSD kept: those with distance_sq <= threshold_sq.
  struct KeptMatches {
    double threshold_sq = 0;
    std::size_t count = 0;
    double max_weight = 0;
    double length_scale = 1;  // L: their RMS distance from the sensor, at least 1 mm
  };

  // align()'s steps, in the order it runs them each iteration.
  void prepare(const PointCloud& reading);
  void remember_search_pose(int iteration, const Eigen::Matrix3d& R, const Eigen::Vector3d& t);
  void associate(const PointCloud& reading, const LocalMap& map, const MatchContext& context, IcpResult& result);
  KeptMatches trim_matches(const Eigen::Vector3d& t);
  NormalEquations normal_equations(const KeptMatches& kept, const Eigen::Vector3d& t, IcpResult& result) const;
  bool converged_after(double rotation_rad, double translation_m);
  double now() const { return clock_ ? clock_() : 0.0; }

  IcpParams params_;
  Clock clock_;
  ParallelRunner* runner_;
  std::vector<WorkerScratch> workers_;
  std::vector<Match> point_matches_;          // match_k slots per reading point
  std::vector<std::uint8_t> point_match_count_;
  std::vector<Match> matches_;                // this iteration's, in reading order
  std::vector<double> distances_sq_;
  std::vector<double> scratch_;
  std::vector<KeptNeighbour> kept_;
  std::vector<std::uint8_t> kept_count_;
  std::vector<double> clear_radius_m_;
  std::vector<int> searched_at_;
  std::vector<double> ranges_m_;
  std::vector<SearchPose> search_poses_;      // per iteration
  std::vector<double> pose_change_rot_rad_;   // per iteration: angle(R · R_jᵀ) for the current R
  std::vector<double> pose_change_trans_m_;
  std::vector<double> recent_rotation_rad_;
  std::vector<double> recent_translation_m_;
};

}  // namespace tumble
