#include "daemon/busiest_sender.hpp"

#include <algorithm>

namespace tumble::daemon {

bool BusiestSender::observe(std::uint32_t src_ip, double arrival_s) {
  // A window closes after kWindow_s, or at once when time ran back.
  if (!started_ || arrival_s - window_start_s_ >= kWindow_s || arrival_s < window_start_s_) {
    for (std::size_t i = 0; i < used_; ++i) {
      senders_[i].previous = started_ ? senders_[i].current : 0;
      senders_[i].current = 0;
    }
    started_ = true;
    window_start_s_ = arrival_s;
  }
  Tally* tally = nullptr;
  for (std::size_t i = 0; i < used_; ++i)
    if (senders_[i].ip == src_ip) tally = &senders_[i];
  if (tally == nullptr) {
    if (used_ < kTracked) {
      tally = &senders_[used_++];
    } else {
      tally = &*std::min_element(senders_.begin(), senders_.end(),
                                 [](const Tally& a, const Tally& b) { return a.total() < b.total(); });
    }
    *tally = Tally{src_ip, 0, 0};
  }
  ++tally->current;

  // The current choice keeps a tie, so that the lidar does not flip-flop.
  const Tally* busiest = tally;
  for (std::size_t i = 0; i < used_; ++i) {
    const Tally& t = senders_[i];
    const bool is_lidar = lidar_ && t.ip == *lidar_;
    if (t.total() > busiest->total() || (t.total() == busiest->total() && is_lidar)) busiest = &t;
  }
  changed_ = !lidar_ || *lidar_ != busiest->ip;
  lidar_ = busiest->ip;
  return src_ip == *lidar_;
}

}  // namespace tumble::daemon
