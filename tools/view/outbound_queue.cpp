#include "tools/view/outbound_queue.hpp"

#include <algorithm>
#include <utility>

namespace tumble::view {

void OutboundQueue::push(FramePtr frame) {
  if (frame->newest_only) {
    const auto same_kind =
        std::find_if(frames_.begin(), frames_.end(), [&](const FramePtr& f) { return f->kind == frame->kind; });
    if (same_kind != frames_.end()) {
      *same_kind = std::move(frame);
      ++dropped_;
      return;
    }
  }
  frames_.push_back(std::move(frame));
  while (frames_.size() > capacity_) {
    frames_.pop_front();
    ++dropped_;
  }
}

FramePtr OutboundQueue::pop() {
  if (frames_.empty()) return nullptr;
  FramePtr front = std::move(frames_.front());
  frames_.pop_front();
  return front;
}

}  // namespace tumble::view
