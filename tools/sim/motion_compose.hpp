// Composition of motions: sequences (each part continues from where the
// previous one ended) and superposition (a motion of B relative to a base).
#pragma once

#include "tools/sim/motion.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace tumble::sim {

// Part k is re-anchored so that its B starts at part k-1's final pose. The
// states must join: velocity, acceleration, angular velocity and angular
// acceleration equal at each junction (throws std::invalid_argument naming
// the part and the quantity otherwise).
class SequenceMotion final : public Motion {
 public:
  explicit SequenceMotion(std::vector<std::unique_ptr<Motion>> parts);
  MotionState at(double t_s) const override;
  double duration_s() const override { return start_s_.empty() ? 0.0 : end_s_; }

 private:
  std::vector<std::unique_ptr<Motion>> parts_;
  std::vector<MotionState> anchors_;  // constant W <- part frame
  std::vector<double> start_s_;
  double end_s_ = 0;
};

// T_wb(t) = base(t) * offset(t): the offset moves B in the base's B frame.
// Duration is the base's; the offset holds its end state once it is over.
class SuperposedMotion final : public Motion {
 public:
  SuperposedMotion(std::unique_ptr<Motion> base, std::unique_ptr<Motion> offset);
  MotionState at(double t_s) const override;
  double duration_s() const override { return base_->duration_s(); }

 private:
  std::unique_ptr<Motion> base_;
  std::unique_ptr<Motion> offset_;
};

// Why two states do not join (nullopt when they do, within tolerance).
std::optional<std::string> join_mismatch(const MotionState& end, const MotionState& start);

}  // namespace tumble::sim
