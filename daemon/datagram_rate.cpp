#include "daemon/datagram_rate.hpp"

namespace tumble::daemon {

void DatagramRate::advance(double arrival_s) {
  if (!started_ || arrival_s < window_start_s_) {  // the first datagram, or time ran back: start afresh
    started_ = true;
    window_start_s_ = arrival_s;
    current_ = previous_ = 0;
    return;
  }
  const double elapsed_s = arrival_s - window_start_s_;
  if (elapsed_s < kWindow_s) return;
  // A window with no datagram at all in between counted nothing.
  previous_ = elapsed_s < 2.0 * kWindow_s ? current_ : 0;
  current_ = 0;
  window_start_s_ = arrival_s;
}

}  // namespace tumble::daemon
