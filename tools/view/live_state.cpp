#include "tools/view/live_state.hpp"

#include <utility>

#include "tools/view/frames.hpp"

namespace tumble::view {

LiveState::LiveState(std::size_t max_history_poses, std::size_t pending_capacity)
    : pending_(pending_capacity), max_history_floats_(3 * max_history_poses) {}

void LiveState::add(FramePtr frame) {
  std::unique_lock lock(mutex_);
  add_locked(std::move(frame), lock);
}

void LiveState::add_pose(FramePtr frame, std::int64_t scan_index, const double position_m[3]) {
  std::unique_lock lock(mutex_);
  if (scan_index < last_scan_index_) history_xyz_.clear();
  last_scan_index_ = scan_index;
  for (int i = 0; i < 3; ++i) history_xyz_.push_back(static_cast<float>(position_m[i]));
  while (history_xyz_.size() > max_history_floats_) history_xyz_.erase(history_xyz_.begin(), history_xyz_.begin() + 3);
  add_locked(std::move(frame), lock);
}

void LiveState::add_locked(FramePtr frame, std::unique_lock<std::mutex>& lock) {
  ++messages_;
  last_message_ = Clock::now();
  if (frame->newest_only) newest_[static_cast<std::size_t>(frame->kind)] = frame;
  const bool was_empty = pending_.empty();
  pending_.push(std::move(frame));
  lock.unlock();
  if (was_empty && notify_) notify_();
}

std::vector<FramePtr> LiveState::take_pending() {
  std::lock_guard lock(mutex_);
  std::vector<FramePtr> out;
  out.reserve(pending_.size());
  while (FramePtr f = pending_.pop()) out.push_back(std::move(f));
  return out;
}

std::vector<FramePtr> LiveState::joining_frames() const {
  std::lock_guard lock(mutex_);
  const std::vector<float> xyz(history_xyz_.begin(), history_xyz_.end());
  std::vector<FramePtr> out{std::make_shared<const Frame>(history_frame(xyz))};
  for (const FramePtr& f : newest_)
    if (f) out.push_back(f);
  return out;
}

std::uint64_t LiveState::messages() const {
  std::lock_guard lock(mutex_);
  return messages_;
}

std::optional<double> LiveState::since_last_s(Clock::time_point now) const {
  std::lock_guard lock(mutex_);
  if (!last_message_) return std::nullopt;
  return std::chrono::duration<double>(now - *last_message_).count();
}

}  // namespace tumble::view
