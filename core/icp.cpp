#include "core/icp.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

namespace tumble {

namespace {

// Eigenvalues below this fraction of the largest are numerically zero: the
// step has no component along them (the initial guess is kept there).
constexpr double kPseudoInverseCutoff = 1e-12;

// The Gauss-Newton step minimising ½xᵀHx + gᵀx with no translation along the
// unit vector `held` (Lagrange: [H e; eᵀ 0]). H may be singular along it: the
// system stays solvable while the other five directions are observed.
Vector6d step_holding_translation(const Matrix6d& H, const Vector6d& g, const Eigen::Vector3d& held) {
  Eigen::Matrix<double, 7, 7> kkt = Eigen::Matrix<double, 7, 7>::Zero();
  kkt.topLeftCorner<6, 6>() = H;
  kkt.block<3, 1>(0, 6) = held;
  kkt.block<1, 3>(6, 0) = held.transpose();
  Eigen::Matrix<double, 7, 1> rhs = Eigen::Matrix<double, 7, 1>::Zero();
  rhs.head<6>() = -g;
  return kkt.fullPivLu().solve(rhs).head<6>();
}

// The Gauss-Newton step minimising ½xᵀHx + gᵀx, from H's eigen-decomposition,
// with no component along its numerically zero eigenvalues (kPseudoInverseCutoff).
Vector6d minimum_norm_step(const Eigen::SelfAdjointEigenSolver<Matrix6d>& eigen, const Vector6d& g) {
  const Vector6d lambda = eigen.eigenvalues();
  Vector6d step = Vector6d::Zero();
  for (int e = 0; e < 6; ++e) {
    const Vector6d v = eigen.eigenvectors().col(e);
    if (lambda(e) > lambda(5) * kPseudoInverseCutoff) step -= v * (v.dot(g) / lambda(e));
  }
  return step;
}

// Fresh neighbour searches reach this factor times max_match_distance_m, and
// keep this many neighbours beyond match_k: the farther the last kept one,
// the larger the moves over which the search can be reused.
constexpr double kReuseMargin = 1.1;
constexpr std::size_t kExtraKept = 3;

Eigen::Matrix3d rotation_exp(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

// s²·H⁻¹ (H's numerically zero eigenvalues floored at kPseudoInverseCutoff),
// back from (t, L·ω) to (t, ω): the covariance of ω is that of L·ω over L².
Matrix6d covariance_of(const Eigen::SelfAdjointEigenSolver<Matrix6d>& eigen, double residual_variance,
                       double length_scale) {
  const Vector6d lambda = eigen.eigenvalues();
  const double cutoff = lambda(5) * kPseudoInverseCutoff;
  Matrix6d H_inv = Matrix6d::Zero();
  for (int e = 0; e < 6; ++e) {
    const Vector6d v = eigen.eigenvectors().col(e);
    const double l = std::max(lambda(e), cutoff);
    H_inv += v * v.transpose() / (l > 0 ? l : std::numeric_limits<double>::min());
  }
  const double inv_l = 1.0 / length_scale;
  Vector6d unscale;
  unscale << 1, 1, 1, inv_l, inv_l, inv_l;
  return residual_variance * unscale.asDiagonal() * H_inv * unscale.asDiagonal();
}

// The Gauss-Newton step in the scaled coordinates. The prior (in the normal
// matrix's units: it holds the covariance s²·H⁻¹; none without a residual
// variance, too few matches to weigh it against) pulls the translation back
// to the prediction, `from_prediction_w` away; a weakest direction that is
// mostly a translation and below `hold_share` of the weights is held, and
// `held_translation_w` says which (zero: none).
Vector6d gauss_newton_step(const NormalEquations& system, const Eigen::SelfAdjointEigenSolver<Matrix6d>& eigen,
                           const Eigen::Matrix3d& prior_information_w, const Eigen::Vector3d& from_prediction_w,
                           double hold_share, Eigen::Vector3d& held_translation_w) {
  const bool prior_now = !prior_information_w.isZero() && system.residual_variance > 0;
  Matrix6d H_step = system.H;
  Vector6d g_step = system.g;
  if (prior_now) {
    H_step.topLeftCorner<3, 3>() += system.residual_variance * prior_information_w;
    g_step.head<3>() += system.residual_variance * prior_information_w * from_prediction_w;
  }
  const Vector6d lambda = eigen.eigenvalues();
  const Vector6d weakest = eigen.eigenvectors().col(0);
  const bool hold = lambda(0) < hold_share * system.weight_sum && mostly_translation(weakest);
  held_translation_w = hold ? Eigen::Vector3d(weakest.head<3>().normalized()) : Eigen::Vector3d::Zero();
  return hold        ? step_holding_translation(H_step, g_step, held_translation_w)
         : prior_now ? minimum_norm_step(Eigen::SelfAdjointEigenSolver<Matrix6d>(H_step), g_step)
                     : minimum_norm_step(eigen, system.g);
}

// How well the last system pins each direction (Degeneracy).
void describe_degeneracy(const Eigen::SelfAdjointEigenSolver<Matrix6d>& eigen, const NormalEquations& system,
                         double degeneracy_ratio, Degeneracy& d) {
  const Vector6d lambda = eigen.eigenvalues();
  d.min_eigenvalue = std::max(lambda(0), 0.0) / system.weight_sum;
  d.residual_variance_per_weight = system.residual_variance / system.weight_sum;
  d.direction = eigen.eigenvectors().col(0);
  d.condition_number = lambda(0) > 0 ? lambda(5) / lambda(0) : std::numeric_limits<double>::infinity();
  d.degenerate = !(lambda(0) >= degeneracy_ratio * lambda(5));
}

void check_params(const IcpParams& p) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("IcpParams: " + what); };
  if (!(p.max_match_distance_m > 0)) fail("max_match_distance_m must be > 0");
  if (p.match_k < 1 || p.match_k > 64) fail("match_k must be in [1, 64]");
  if (!(p.frmsd_r_min > 0 && p.frmsd_r_min <= p.frmsd_r_max && p.frmsd_r_max <= 1))
    fail("need 0 < frmsd_r_min <= frmsd_r_max <= 1");
  if (!(p.frmsd_lambda >= 0)) fail("frmsd_lambda must be >= 0");
  if (p.max_iterations < 1) fail("max_iterations must be >= 1");
  if (p.averaged_window < 1) fail("averaged_window must be >= 1");
  if (!(p.max_normal_angle_deg > 0)) fail("max_normal_angle_deg must be > 0");
  if (!(p.hold_weak_translation_share >= 0 && p.hold_weak_translation_share <= 1))
    fail("hold_weak_translation_share must be in [0, 1]");
}

}  // namespace

FrmsdTrim frmsd_trim(std::span<const double> squared_distances, double r_min, double r_max, double lambda,
                     std::vector<double>& scratch) {
  FrmsdTrim trim;
  const std::size_t n = squared_distances.size();
  if (n == 0) return trim;
  const std::size_t k_lo = std::max<std::size_t>(1, static_cast<std::size_t>(std::floor(r_min * n)));
  const std::size_t k_hi = std::max(k_lo, static_cast<std::size_t>(std::floor(r_max * n)));
  scratch.assign(squared_distances.begin(), squared_distances.end());
  // Only the k_hi smallest matter, and only those from rank k_lo on in order:
  // the k_lo − 1 smallest enter as one sum.
  const auto first = scratch.begin();
  const auto lo = first + static_cast<std::ptrdiff_t>(k_lo - 1);
  const auto hi = first + static_cast<std::ptrdiff_t>(k_hi);
  std::nth_element(first, lo, scratch.end());
  std::nth_element(lo, hi - 1, scratch.end());
  std::sort(lo, hi);
  double sum = 0;
  for (auto it = first; it != lo; ++it) sum += *it;
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_k = k_lo;
  for (std::size_t k = k_lo; k <= k_hi; ++k) {
    sum += scratch[k - 1];
    const double r = static_cast<double>(k) / static_cast<double>(n);
    // FRMSD² (same minimiser, no square root per candidate).
    const double frmsd_sq = (sum / static_cast<double>(k)) / std::pow(r, 2 * lambda);
    if (frmsd_sq < best) {
      best = frmsd_sq;
      best_k = k;
    }
  }
  trim.kept = best_k;
  trim.ratio = static_cast<double>(best_k) / static_cast<double>(n);
  trim.threshold_sq = scratch[best_k - 1];
  return trim;
}

Icp::Icp(const IcpParams& params, Clock clock, ParallelRunner& runner)
    : params_(params), clock_(std::move(clock)), runner_(&runner), workers_(runner.workers()) {
  check_params(params);
  for (WorkerScratch& scratch : workers_) {
    scratch.neighbours.resize(static_cast<std::size_t>(params.match_k) + kExtraKept);
    scratch.ranked.resize(static_cast<std::size_t>(params.match_k) + kExtraKept);
  }
  const auto iterations = static_cast<std::size_t>(params.max_iterations);
  search_poses_.resize(iterations);
  pose_change_rot_rad_.resize(iterations);
  pose_change_trans_m_.resize(iterations);
  recent_rotation_rad_.reserve(iterations);
  recent_translation_m_.reserve(iterations);
}

std::size_t Icp::neighbours_of(std::size_t i, const Eigen::Vector3d& p_w, int iteration, const LocalMap& map,
                               double displacement_m, WorkerScratch& scratch) {
  std::vector<RankedNeighbour>& ranked = scratch.ranked;
  std::vector<Neighbour>& found = scratch.neighbours;
  const std::size_t k = static_cast<std::size_t>(params_.match_k);
  const std::size_t kept_capacity = k + kExtraKept;
  const double max_sq = params_.max_match_distance_m * params_.max_match_distance_m;
  KeptNeighbour* kept = kept_.data() + i * kept_capacity;
  std::size_t count = kept_count_[i];
  if (iteration > 0 && params_.reuse_neighbours) {
    // Re-rank the kept neighbours at the new pose (insertion sort: a few).
    for (std::size_t j = 0; j < count; ++j) {
      const RankedNeighbour candidate{(kept[j].p_w - p_w).squaredNorm(), &kept[j]};
      std::size_t m = j;
      while (m > 0 && ranked[m - 1].distance_sq > candidate.distance_sq) {
        ranked[m] = ranked[m - 1];
        --m;
      }
      ranked[m] = candidate;
    }
    std::size_t matched = 0;
    while (matched < std::min(count, k) && ranked[matched].distance_sq < max_sq) ++matched;
    // Unkept map points are at least clear − δ away now: they can neither
    // beat the k-th kept neighbour nor come within the match distance.
    const double clear = clear_radius_m_[i] - displacement_m - 1e-9;
    const bool exact = matched == k ? ranked[k - 1].distance_sq < clear * clear : clear >= params_.max_match_distance_m;
    if (clear > 0 && exact) return matched;
  }
  // A fresh search, a margin beyond the match distance so that the next
  // iterations' small moves stay inside what it saw.
  const double search_radius = params_.max_match_distance_m * kReuseMargin;
  count = map.knn(p_w, search_radius, found);
  ++scratch.searches;
  for (std::size_t j = 0; j < count; ++j) {
    const std::uint32_t index = found[j].index;
    kept[j] = KeptNeighbour{map.position(index), Eigen::Vector3d::Zero(), map.point(index).variance_m2, index,
                            false, false};
    ranked[j] = RankedNeighbour{found[j].distance_sq, &kept[j]};
  }
  kept_count_[i] = static_cast<std::uint8_t>(count);
  clear_radius_m_[i] = count == kept_capacity ? std::sqrt(found[count - 1].distance_sq) : search_radius;
  searched_at_[i] = iteration;
  std::size_t matched = 0;
  while (matched < std::min(count, k) && ranked[matched].distance_sq < max_sq) ++matched;
  return matched;
}

std::size_t Icp::match_point(std::size_t i, const PointCloud& reading, const LocalMap& map,
                             const MatchContext& context, WorkerScratch& scratch, Match* out) {
  const Eigen::Vector3d p_w = context.R * reading.points[i] + context.t;
  const auto since = static_cast<std::size_t>(searched_at_[i]);
  const double moved =
      context.iteration > 0 ? pose_change_trans_m_[since] + pose_change_rot_rad_[since] * ranges_m_[i] : 0.0;
  const std::size_t found = neighbours_of(i, p_w, context.iteration, map, moved, scratch);
  if (found == 0) return 0;
  const double read_var = reading.sigma_n_m[i] * reading.sigma_n_m[i] + reading.sigma_s_m[i] * reading.sigma_s_m[i];
  const bool check_normal = reading.normal_valid[i] != 0 && context.min_normal_cos > 0;
  const Eigen::Vector3d read_normal_w =
      check_normal ? Eigen::Vector3d(context.R * reading.normals[i]) : Eigen::Vector3d::Zero();
  std::size_t count = 0;
  for (std::size_t j = 0; j < found; ++j) {
    KeptNeighbour& q = *scratch.ranked[j].neighbour;
    if (!q.normal_read) {
      const MapPoint& fitted = map.fitted_point(q.map_index, scratch.fit_neighbours, scratch.own_fit);
      q.normal_w = fitted.normal_w.cast<double>();
      q.normal_valid = fitted.normal_valid;
      q.normal_read = true;
    }
    if (!q.normal_valid) continue;
    if (check_normal && std::abs(read_normal_w.dot(q.normal_w)) < context.min_normal_cos) continue;
    double w;
    if (params_.weighting == MatchWeighting::kPointWeight) {
      w = reading.weights[i];
    } else {
      const double var = read_var + q.variance;
      w = var > 0 ? 1.0 / var : 0.0;
    }
    if (!(w > 0) || !std::isfinite(w)) continue;
    const double trim_sq = params_.trim_distance == TrimDistance::kMatch
                               ? scratch.ranked[j].distance_sq
                               : [&] { const double r = q.normal_w.dot(p_w - q.p_w); return r * r; }();
    out[count++] = Match{p_w, q.p_w, q.normal_w, trim_sq, w};
  }
  return count;
}

IcpResult Icp::align(const PointCloud& reading, const LocalMap& map, const Eigen::Isometry3d& initial_T_wl,
                     const Eigen::Matrix3d& prior_information_w) {
  IcpResult result;
  Eigen::Matrix3d R = initial_T_wl.rotation();
  Eigen::Vector3d t = initial_T_wl.translation();
  recent_rotation_rad_.clear();
  recent_translation_m_.clear();
  // Normals can only agree up to the estimate's own rotation error, which is
  // unknown until it has converged: the normal test starts then, and the
  // iterations go on until the estimate converges with it.
  const bool use_normal_test = params_.max_normal_angle_deg < 90.0;
  const double normal_test_cos = std::cos(std::min(params_.max_normal_angle_deg, 90.0) * std::numbers::pi / 180.0);
  bool normal_test_on = false;
  // A prior that is not finite (a covariance gone wrong upstream) is no prior.
  const Eigen::Matrix3d prior_w =
      prior_information_w.allFinite() && !prior_information_w.isZero() ? prior_information_w : Eigen::Matrix3d::Zero();
  prepare(reading);

  Eigen::SelfAdjointEigenSolver<Matrix6d> eigen;
  NormalEquations system;  // the last one built
  bool have_system = false;
  double clock_mark = now();

  for (int iteration = 0; iteration < params_.max_iterations; ++iteration) {
    remember_search_pose(iteration, R, t);
    associate(reading, map, MatchContext{R, t, iteration, normal_test_on ? normal_test_cos : 0.0}, result);
    if (matches_.size() < 6) {
      const double t_end = now();
      result.matching_s += t_end - clock_mark;
      break;
    }
    const KeptMatches kept = trim_matches(t);
    {
      const double t_matched = now();
      result.matching_s += t_matched - clock_mark;
      clock_mark = t_matched;
    }
    if (kept.count < 6) break;

    system = normal_equations(kept, t, result);
    eigen.compute(system.H);
    const Vector6d step_scaled =
        gauss_newton_step(system, eigen, prior_w, t - initial_T_wl.translation(), params_.hold_weak_translation_share,
                          result.held_translation_w);
    have_system = true;
    result.covariance = covariance_of(eigen, system.residual_variance, system.length_scale);

    // Back to (t, ω): the step in L·ω divided by L.
    const double inv_l = 1.0 / system.length_scale;
    const Eigen::Vector3d d_t = step_scaled.head<3>();
    const Eigen::Vector3d d_w = step_scaled.tail<3>() * inv_l;
    R = rotation_exp(d_w) * R;
    t += d_t;
    result.iterations = iteration + 1;
    const bool converged = converged_after(d_w.norm(), d_t.norm());
    {
      const double t_solved = now();
      result.solve_s += t_solved - clock_mark;
      clock_mark = t_solved;
    }
    if (converged && use_normal_test && !normal_test_on) {
      // The increments so far stay in the window: one more small step with
      // the normal test converges.
      normal_test_on = true;
    } else if (converged) {
      result.converged = true;
      break;
    }
  }

  for (const WorkerScratch& scratch : workers_) result.neighbour_searches += scratch.searches;
  Eigen::Quaterniond q(R);
  q.normalize();
  result.T_wl.linear() = q.toRotationMatrix();
  result.T_wl.translation() = t;
  result.degeneracy.length_scale_m = system.length_scale;
  if (have_system && system.weight_sum > 0) {
    describe_degeneracy(eigen, system, params_.degeneracy_ratio, result.degeneracy);
  } else {
    result.covariance = Matrix6d::Identity() * std::numeric_limits<double>::infinity();
  }
  return result;
}

void Icp::prepare(const PointCloud& reading) {
  const std::size_t n = reading.size();
  const std::size_t k = static_cast<std::size_t>(params_.match_k);
  kept_.resize(n * (k + kExtraKept));
  point_matches_.resize(n * k);
  point_match_count_.resize(n);
  kept_count_.resize(n);
  clear_radius_m_.resize(n);
  searched_at_.resize(n);
  ranges_m_.resize(n);
  for (std::size_t i = 0; i < n; ++i) ranges_m_[i] = reading.points[i].norm();
  for (WorkerScratch& scratch : workers_) scratch.searches = 0;
}

// How far the current pose moves a point of range r from where it was at
// each earlier iteration's pose: at most trans + rot · r.
void Icp::remember_search_pose(int iteration, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  const auto it_index = static_cast<std::size_t>(iteration);
  search_poses_[it_index] = SearchPose{R, t};
  for (std::size_t j = 0; j < it_index; ++j) {
    pose_change_rot_rad_[j] = Eigen::AngleAxisd(R * search_poses_[j].R.transpose()).angle();
    pose_change_trans_m_[j] = (t - search_poses_[j].t).norm();
  }
}

// The points spread over the runner's threads: each writes its own match
// slots, gathered into matches_ in reading order.
void Icp::associate(const PointCloud& reading, const LocalMap& map, const MatchContext& context,
                    IcpResult& result) {
  const std::size_t n = reading.size();
  const std::size_t k = static_cast<std::size_t>(params_.match_k);
  runner_->run(n, [&](std::size_t worker, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      point_match_count_[i] =
          static_cast<std::uint8_t>(match_point(i, reading, map, context, workers_[worker], &point_matches_[i * k]));
  });
  matches_.clear();
  for (std::size_t i = 0; i < n; ++i)
    matches_.insert(matches_.end(), point_matches_.begin() + static_cast<std::ptrdiff_t>(i * k),
                    point_matches_.begin() + static_cast<std::ptrdiff_t>(i * k + point_match_count_[i]));
  result.matches_considered = matches_.size();
  result.matched_ratio = static_cast<double>(std::count_if(point_match_count_.begin(),
                                                           point_match_count_.begin() + static_cast<std::ptrdiff_t>(n),
                                                           [](std::uint8_t c) { return c > 0; })) /
                         static_cast<double>(n);
}

// Outlier rejection (FRMSD) on the chosen distance.
Icp::KeptMatches Icp::trim_matches(const Eigen::Vector3d& t) {
  distances_sq_.resize(matches_.size());
  for (std::size_t m = 0; m < matches_.size(); ++m) distances_sq_[m] = matches_[m].distance_sq;
  KeptMatches kept;
  kept.threshold_sq =
      frmsd_trim(distances_sq_, params_.frmsd_r_min, params_.frmsd_r_max, params_.frmsd_lambda, scratch_).threshold_sq;
  double range_sq_sum = 0;
  for (const Match& m : matches_) {
    if (m.distance_sq > kept.threshold_sq) continue;
    kept.max_weight = std::max(kept.max_weight, m.weight);
    range_sq_sum += (m.p_w - t).squaredNorm();
    ++kept.count;
  }
  if (kept.count > 0) kept.length_scale = std::max(std::sqrt(range_sq_sum / static_cast<double>(kept.count)), 1e-3);
  return kept;
}

// In the scaled coordinates (t, L·ω): J = [n, (p − t) × n / L].
NormalEquations Icp::normal_equations(const KeptMatches& kept, const Eigen::Vector3d& t, IcpResult& result) const {
  NormalEquations system;
  system.length_scale = kept.length_scale;
  double weighted_sq_sum = 0;
  const double inv_l = 1.0 / kept.length_scale;
  for (const Match& m : matches_) {
    if (m.distance_sq > kept.threshold_sq) continue;
    const double w = m.weight / kept.max_weight;
    const double r = m.normal_w.dot(m.p_w - m.q_w);
    Vector6d J;
    J.head<3>() = m.normal_w;
    J.tail<3>() = (m.p_w - t).cross(m.normal_w) * inv_l;
    system.H.noalias() += w * J * J.transpose();
    system.g.noalias() += w * r * J;
    weighted_sq_sum += w * r * r;
    system.weight_sum += w;
  }
  result.matches_kept = kept.count;
  result.inlier_ratio = static_cast<double>(kept.count) / static_cast<double>(matches_.size());
  result.residual_rms_m = std::sqrt(weighted_sq_sum / system.weight_sum);
  const double dof = static_cast<double>(kept.count) - 6.0;
  system.residual_variance = dof > 0 ? weighted_sq_sum / dof : 0.0;
  return system;
}

bool Icp::converged_after(double rotation_rad, double translation_m) {
  if (params_.convergence == ConvergenceCriterion::kIncrementBelow)
    return rotation_rad < params_.increment_rotation_rad && translation_m < params_.increment_translation_m;
  recent_rotation_rad_.push_back(rotation_rad);
  recent_translation_m_.push_back(translation_m);
  const std::size_t w = static_cast<std::size_t>(params_.averaged_window);
  if (recent_rotation_rad_.size() < w) return false;
  const double mean_rot =
      std::accumulate(recent_rotation_rad_.end() - static_cast<std::ptrdiff_t>(w), recent_rotation_rad_.end(), 0.0) / w;
  const double mean_trans =
      std::accumulate(recent_translation_m_.end() - static_cast<std::ptrdiff_t>(w), recent_translation_m_.end(), 0.0) / w;
  return mean_rot < params_.averaged_rotation_rad && mean_trans < params_.averaged_translation_m;
}

}  // namespace tumble
