#include "tools/sim/motion_compose.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace tumble::sim {

std::optional<std::string> join_mismatch(const MotionState& end, const MotionState& start) {
  // Loose enough for rounding in long chains, far below any physical step.
  constexpr double kTolerance = 1e-7;
  struct Quantity {
    const char* name;
    Eigen::Vector3d a, b;
    const char* unit;
  };
  const Quantity quantities[] = {
      {"velocity", end.v_w, start.v_w, "m/s"},
      {"acceleration", end.a_w, start.a_w, "m/s^2"},
      {"angular velocity", end.omega_b, start.omega_b, "rad/s"},
      {"angular acceleration", end.alpha_b, start.alpha_b, "rad/s^2"},
  };
  for (const Quantity& q : quantities) {
    if ((q.a - q.b).norm() <= kTolerance) continue;
    std::ostringstream why;
    why << q.name << " jumps from [" << q.a.transpose() << "] to [" << q.b.transpose() << "] " << q.unit;
    return why.str();
  }
  return std::nullopt;
}

SequenceMotion::SequenceMotion(std::vector<std::unique_ptr<Motion>> parts) : parts_(std::move(parts)) {
  double t = 0;
  for (std::size_t k = 0; k < parts_.size(); ++k) {
    const MotionState first = parts_[k]->at(0.0);
    MotionState anchor;  // identity for the first part
    if (k > 0) {
      const MotionState previous_end = compose(anchors_.back(), parts_[k - 1]->at(parts_[k - 1]->duration_s()));
      anchor = at_rest(previous_end.T_wb * first.T_wb.inverse());
      if (auto why = join_mismatch(previous_end, compose(anchor, first)))
        throw std::invalid_argument("part " + std::to_string(k) + " does not continue part " + std::to_string(k - 1) +
                                    ": " + *why);
    }
    anchors_.push_back(anchor);
    start_s_.push_back(t);
    t += parts_[k]->duration_s();
  }
  end_s_ = t;
}

MotionState SequenceMotion::at(double t_s) const {
  if (parts_.empty()) return {};
  const double t = std::clamp(t_s, 0.0, end_s_);
  const auto it = std::upper_bound(start_s_.begin(), start_s_.end(), t);
  const std::size_t k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - start_s_.begin() - 1, 0));
  return compose(anchors_[k], parts_[k]->at(t - start_s_[k]));
}

SuperposedMotion::SuperposedMotion(std::unique_ptr<Motion> base, std::unique_ptr<Motion> offset)
    : base_(std::move(base)), offset_(std::move(offset)) {}

MotionState SuperposedMotion::at(double t_s) const {
  const double t = std::clamp(t_s, 0.0, base_->duration_s());
  return compose(base_->at(t), offset_->at(t));
}

}  // namespace tumble::sim
