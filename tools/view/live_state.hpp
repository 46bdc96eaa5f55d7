// What the LCM thread has received, handed to the web thread: the frames not
// yet sent to browsers (bounded, newest-only kinds coalesced), the newest
// frame of each kind and the trajectory so far for a browser that joins
// (bounded: the oldest poses go). Safe between the two threads.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <vector>

#include "tools/view/outbound_queue.hpp"

namespace tumble::view {

class LiveState {
 public:
  using Clock = std::chrono::steady_clock;
  // max_history_poses: the trajectory a joining browser gets, newest kept.
  explicit LiveState(std::size_t max_history_poses = 20000, std::size_t pending_capacity = 256);

  // Called (on the adding thread) when frames become pending after none were:
  // one hand-over is scheduled at a time, however fast frames arrive.
  void on_pending(std::function<void()> notify) { notify_ = std::move(notify); }

  // LCM thread. A pose's position extends the trajectory; a scan index lower
  // than the last one starts a new trajectory (tumbled restarted).
  void add(FramePtr frame);
  void add_pose(FramePtr frame, std::int64_t scan_index, const double position_m[3]);

  // Web thread.
  std::vector<FramePtr> take_pending();
  std::vector<FramePtr> joining_frames() const;  // history, then the newest of each kind
  std::uint64_t messages() const;
  std::optional<double> since_last_s(Clock::time_point now) const;

 private:
  void add_locked(FramePtr frame, std::unique_lock<std::mutex>& lock);

  mutable std::mutex mutex_;
  OutboundQueue pending_;
  std::array<FramePtr, 7> newest_{};  // by FrameKind, newest-only kinds
  std::deque<float> history_xyz_;
  std::size_t max_history_floats_;
  std::int64_t last_scan_index_ = -1;
  std::uint64_t messages_ = 0;
  std::optional<Clock::time_point> last_message_;
  std::function<void()> notify_;
};

}  // namespace tumble::view
