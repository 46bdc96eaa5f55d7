#include "core/unobserved_direction.hpp"

#include <stdexcept>
#include <string>

namespace tumble {

void check_unobserved_direction_params(const UnobservedDirectionParams& p) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("UnobservedDirectionParams: " + what); };
  if (!(p.weak_min_eigenvalue >= 0 && p.weak_min_eigenvalue <= 1)) fail("weak_min_eigenvalue must be in [0, 1]");
  if (p.window_scans < 1) fail("window_scans must be >= 1");
  if (!(p.enter_fraction > 0 && p.enter_fraction <= 1)) fail("enter_fraction must be in (0, 1]");
  if (!(p.sigma_m > 0)) fail("sigma_m must be > 0");
}

UnobservedDirection::UnobservedDirection(const UnobservedDirectionParams& params) : params_(params) {
  check_unobserved_direction_params(params_);
  weak_.assign(params_.window_scans, false);
}

bool UnobservedDirection::add(const Degeneracy& degeneracy) {
  const bool weak = this->weak(degeneracy);
  if (filled_ == weak_.size()) {
    weak_count_ -= weak_[next_] ? 1 : 0;
  } else {
    ++filled_;
  }
  weak_[next_] = weak;
  if (weak) direction_ = weakest_direction(degeneracy);
  weak_count_ += weak ? 1 : 0;
  next_ = (next_ + 1) % weak_.size();
  // Judged over a full window only: a run's first scans say little.
  const double fraction = static_cast<double>(weak_count_) / static_cast<double>(weak_.size());
  const bool was_unobserved = unobserved_;
  if (filled_ == weak_.size() && fraction >= params_.enter_fraction) unobserved_ = true;
  if (fraction < 0.5 * params_.enter_fraction) unobserved_ = false;
  spell_ended_ = was_unobserved && !unobserved_;
  if (unobserved_) since_spell_ = true;
  if (weak_count_ == 0) since_spell_ = false;
  return unobserved_;
}

void UnobservedDirection::widen(Matrix6d& covariance) const { widen_along(covariance, direction_, params_.sigma_m); }

Vector6d weakest_direction(const Degeneracy& degeneracy) {
  Vector6d direction = degeneracy.direction;
  direction.tail<3>() /= degeneracy.length_scale_m;
  return direction;
}

void widen_along(Matrix6d& covariance, const Vector6d& direction, double sigma_m) {
  covariance += sigma_m * sigma_m * direction * direction.transpose();
}

}  // namespace tumble
