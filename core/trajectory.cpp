// See trajectory.hpp for the interpolation, the prefix sums and the frame choice.
#include "core/trajectory.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/rotation.hpp"

namespace tumble {

namespace {

constexpr std::size_t index_of(bool deskewed) { return deskewed ? 1 : 0; }

Eigen::Isometry3d make_pose(const Eigen::Quaterniond& q, const Eigen::Vector3d& p) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.toRotationMatrix();
  pose.translation() = p;
  return pose;
}

// Constant velocity and body rate from one sample, dt_s before or after it.
Eigen::Isometry3d extrapolate(const TrajectorySample& s, double dt_s) {
  return make_pose(integrate_body_rate(s.q_wl, s.omega_l, dt_s), s.p_w + s.v_w * dt_s);
}

}  // namespace

Trajectory::Trajectory(std::size_t capacity, const SpeedUncertaintyParams& params)
    : ring_(capacity), params_(params) {
  if (capacity < 2) throw std::invalid_argument("Trajectory: capacity must be at least 2 samples");
}

void Trajectory::push_back(const TrajectorySample& sample) {
  if (!empty() && !(sample.t_s > back().t_s)) {
    std::ostringstream message;
    message.precision(17);
    message << "Trajectory::push_back: time " << sample.t_s << " s is not after the last sample's " << back().t_s
            << " s";
    throw std::invalid_argument(message.str());
  }
  Entry next;
  next.sample = sample;
  const Eigen::Vector3d v_l = sample.q_wl.conjugate() * sample.v_w;
  for (const bool deskewed : {false, true}) {
    SpeedSigmas& sigma = next.sigma[index_of(deskewed)];
    for (int k = 0; k < 3; ++k) {
      sigma.linear_m_s[k] = linear_speed_sigma(v_l[k], sample.accel_saturated[k], deskewed, params_);
      sigma.angular_rad_s[k] = angular_rate_sigma(sample.omega_l[k], sample.gyro_saturated[k], deskewed, params_);
    }
  }
  if (!empty()) {
    const Entry& last = ring_.back();
    const double dt = sample.t_s - last.sample.t_s;
    for (std::size_t m = 0; m < 2; ++m) {
      next.cumulative[m].delta_m =
          last.cumulative[m].delta_m + 0.5 * dt * (last.sigma[m].linear_m_s + next.sigma[m].linear_m_s);
      next.cumulative[m].theta_rad =
          last.cumulative[m].theta_rad + 0.5 * dt * (last.sigma[m].angular_rad_s + next.sigma[m].angular_rad_s);
    }
  }
  ring_.push_back(next);
}

void Trajectory::truncate_after(double t_s) {
  while (!empty() && back().t_s > t_s) ring_.pop_back();
}

void Trajectory::clear() { ring_.clear(); }

std::size_t Trajectory::locate(double t_s, std::size_t& hint) const {
  const std::size_t last_segment = size() - 2;
  auto contains = [&](std::size_t i) {
    return (i == 0 || ring_[i].sample.t_s <= t_s) && (i == last_segment || t_s < ring_[i + 1].sample.t_s);
  };
  if (hint <= last_segment && contains(hint)) return hint;
  if (hint < last_segment && contains(hint + 1)) return ++hint;
  // Largest i with t_i ≤ t, within [0, last_segment].
  std::size_t lo = 0, hi = last_segment;
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo + 1) / 2;
    if (ring_[mid].sample.t_s <= t_s) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  hint = lo;
  return lo;
}

Eigen::Isometry3d Trajectory::pose_at(double t_s) const {
  std::size_t hint = 0;
  return pose_at(t_s, hint);
}

Eigen::Vector3d Trajectory::velocity_at(double t_s) const {
  if (empty()) throw std::logic_error("Trajectory::velocity_at: empty trajectory");
  if (t_s <= front().t_s) return front().v_w;
  if (t_s >= back().t_s) return back().v_w;
  std::size_t hint = 0;
  const std::size_t i = locate(t_s, hint);
  const TrajectorySample& a = ring_[i].sample;
  const TrajectorySample& b = ring_[i + 1].sample;
  const double u = (t_s - a.t_s) / (b.t_s - a.t_s);
  return (1 - u) * a.v_w + u * b.v_w;
}

Eigen::Vector3d Trajectory::velocity_variance_at(double t_s) const {
  if (empty()) throw std::logic_error("Trajectory::velocity_variance_at: empty trajectory");
  if (size() == 1 || t_s <= front().t_s) return front().velocity_var_w_m2_s2;
  std::size_t hint = 0;
  const std::size_t i = locate(t_s, hint);
  return (t_s >= ring_[i + 1].sample.t_s ? ring_[i + 1] : ring_[i]).sample.velocity_var_w_m2_s2;
}

Eigen::Isometry3d Trajectory::pose_at(double t_s, std::size_t& hint) const {
  if (empty()) throw std::logic_error("Trajectory::pose_at: the trajectory is empty");
  if (t_s <= front().t_s) return extrapolate(front(), t_s - front().t_s);
  if (t_s >= back().t_s) return extrapolate(back(), t_s - back().t_s);
  const std::size_t i = locate(t_s, hint);
  const TrajectorySample& a = ring_[i].sample;
  const TrajectorySample& b = ring_[i + 1].sample;
  const double u = (t_s - a.t_s) / (b.t_s - a.t_s);
  return make_pose(a.q_wl.slerp(u, b.q_wl), a.p_w + u * (b.p_w - a.p_w));
}

Eigen::Isometry3d Trajectory::relative_pose(double t_from_s, double t_to_s) const {
  return pose_at(t_from_s).inverse(Eigen::Isometry) * pose_at(t_to_s);
}

SkewPerturbation Trajectory::cumulative_skew(double t_s, bool deskewed, std::size_t& hint) const {
  if (empty()) throw std::logic_error("Trajectory::cumulative_skew: the trajectory is empty");
  const std::size_t m = index_of(deskewed);
  auto held = [&](const Entry& e, double dt) {
    return SkewPerturbation{e.cumulative[m].delta_m + dt * e.sigma[m].linear_m_s,
                            e.cumulative[m].theta_rad + dt * e.sigma[m].angular_rad_s};
  };
  if (t_s <= front().t_s) return held(ring_.front(), t_s - front().t_s);
  if (t_s >= back().t_s) return held(ring_.back(), t_s - back().t_s);
  const std::size_t i = locate(t_s, hint);
  const Entry& a = ring_[i];
  const Entry& b = ring_[i + 1];
  const double dt = t_s - a.sample.t_s;
  const double u = dt / (b.sample.t_s - a.sample.t_s);
  // Trapezoid over [t_a, t]: the integrand at t is the linear blend of the ends.
  const Eigen::Vector3d linear_at_t = a.sigma[m].linear_m_s + u * (b.sigma[m].linear_m_s - a.sigma[m].linear_m_s);
  const Eigen::Vector3d angular_at_t =
      a.sigma[m].angular_rad_s + u * (b.sigma[m].angular_rad_s - a.sigma[m].angular_rad_s);
  return SkewPerturbation{a.cumulative[m].delta_m + 0.5 * dt * (a.sigma[m].linear_m_s + linear_at_t),
                          a.cumulative[m].theta_rad + 0.5 * dt * (a.sigma[m].angular_rad_s + angular_at_t)};
}

SkewPerturbation Trajectory::skew_integral(double t_from_s, double t_to_s, bool deskewed) const {
  std::size_t hint = 0;
  const SkewPerturbation from = cumulative_skew(t_from_s, deskewed, hint);
  const SkewPerturbation to = cumulative_skew(t_to_s, deskewed, hint);
  return SkewPerturbation{to.delta_m - from.delta_m, to.theta_rad - from.theta_rad};
}

RelativePoseInterpolator::RelativePoseInterpolator(const Trajectory& trajectory, double t_ref_s)
    : trajectory_(trajectory), reference_inverse_(trajectory.pose_at(t_ref_s).inverse(Eigen::Isometry)) {}

Eigen::Isometry3d RelativePoseInterpolator::to_reference(double t_s) {
  return reference_inverse_ * trajectory_.pose_at(t_s, hint_);
}

namespace {

// sin(x) for |x| <= 0.5 by its Taylor series to x^15 (remainder < 1e-17 · |x|),
// else std::sin: the slerp angles of a 100 Hz trajectory are small.
double sin_series(double x) {
  if (!(std::abs(x) <= 0.5)) return std::sin(x);
  const double x2 = x * x;
  return x * (1 + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 +
         x2 * (-1.0 / 39916800 + x2 * (1.0 / 6227020800 + x2 * (-1.0 / 1307674368000))))))));
}

}  // namespace

bool RelativePoseInterpolator::prepare(double t_s) {
  if (segment_ != static_cast<std::size_t>(-1) && t_s >= t_a_s_ && t_s < t_b_s_) return true;
  if (trajectory_.size() < 2 || !(t_s > trajectory_.t_begin_s() && t_s < trajectory_.t_end_s())) return false;
  segment_ = trajectory_.locate(t_s, hint_);
  const TrajectorySample& a = trajectory_.ring_[segment_].sample;
  const TrajectorySample& b = trajectory_.ring_[segment_ + 1].sample;
  t_a_s_ = a.t_s;
  t_b_s_ = b.t_s;
  inv_dt_ = 1.0 / (b.t_s - a.t_s);
  // Eigen's slerp: the angle between the two, the shorter way round.
  const double d = a.q_wl.dot(b.q_wl);
  const double abs_d = std::abs(d);
  const bool linear = abs_d >= 1.0 - Eigen::NumTraits<double>::epsilon();
  theta_ = linear ? 0.0 : std::acos(abs_d);
  inv_sin_theta_ = linear ? 0.0 : 1.0 / std::sin(theta_);
  const Eigen::Quaterniond q_ref_inverse(reference_inverse_.linear());
  qa_ = (q_ref_inverse * a.q_wl).coeffs();
  qb_ = (q_ref_inverse * b.q_wl).coeffs() * (d < 0 ? -1.0 : 1.0);
  pa_ = reference_inverse_ * a.p_w;
  dp_ = reference_inverse_.linear() * (b.p_w - a.p_w);
  return true;
}

Eigen::Vector3d RelativePoseInterpolator::point_to_reference(double t_s, const Eigen::Vector3d& p) {
  if (!prepare(t_s)) return to_reference(t_s) * p;
  const double u = (t_s - t_a_s_) * inv_dt_;
  double w0 = 1.0 - u, w1 = u;
  if (theta_ > 0) {
    w0 = sin_series((1.0 - u) * theta_) * inv_sin_theta_;
    w1 = sin_series(u * theta_) * inv_sin_theta_;
  }
  const Eigen::Quaterniond q(Eigen::Vector4d(w0 * qa_ + w1 * qb_));
  return q * p + pa_ + u * dp_;
}

SkewIntegrator::SkewIntegrator(const Trajectory& trajectory, double t_start_s, bool deskewed)
    : trajectory_(trajectory), deskewed_(deskewed), start_(trajectory.cumulative_skew(t_start_s, deskewed, hint_)) {}

SkewPerturbation SkewIntegrator::until(double t_s) {
  const SkewPerturbation at = trajectory_.cumulative_skew(t_s, deskewed_, hint_);
  return SkewPerturbation{at.delta_m - start_.delta_m, at.theta_rad - start_.theta_rad};
}

}  // namespace tumble
