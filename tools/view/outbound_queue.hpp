// A bounded queue of frames for one receiver (a browser, or the hand-over
// from the LCM thread to the web thread). Frames of a kind where only the
// newest matters (status, scan, map, pose of the moment) replace a waiting
// one of their kind; the others (trajectory poses) queue, and past the
// capacity the oldest frame goes. So a slow browser costs a fixed amount of
// memory and sees the newest state when it catches up.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>

namespace tumble::view {

enum class FrameKind : std::uint8_t { kLink, kStatus, kOdometry, kPose, kScan, kMap, kHistory };

struct Frame {
  FrameKind kind;
  bool binary;        // a WebSocket binary message (points), else JSON text
  bool newest_only;   // replaces a waiting frame of its kind
  std::string bytes;
};

using FramePtr = std::shared_ptr<const Frame>;

class OutboundQueue {
 public:
  explicit OutboundQueue(std::size_t capacity) : capacity_(capacity) {}

  void push(FramePtr frame);
  FramePtr pop();  // nullptr when empty
  bool empty() const { return frames_.empty(); }
  std::size_t size() const { return frames_.size(); }
  std::uint64_t dropped() const { return dropped_; }

 private:
  std::size_t capacity_;
  std::deque<FramePtr> frames_;
  std::uint64_t dropped_ = 0;
};

}  // namespace tumble::view
