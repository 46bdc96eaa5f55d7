// Datagrams per second over whole windows of arrival time: how fast a
// foreign host sends to the lidar's port. At a lidar's rate it is a second
// lidar (or a replay) on the network, which the health state reports.
#pragma once

#include <cstdint>

namespace tumble::daemon {

class DatagramRate {
 public:
  static constexpr double kWindow_s = 1.0;

  // Called with every datagram's arrival (counted or not), so that windows
  // close while the counted traffic is silent.
  void advance(double arrival_s);
  void count() { ++current_; }
  // Of the last whole window; 0 when the one before now saw nothing.
  double rate_hz() const { return static_cast<double>(previous_) / kWindow_s; }

 private:
  bool started_ = false;
  double window_start_s_ = 0.0;
  std::uint64_t current_ = 0;
  std::uint64_t previous_ = 0;
};

}  // namespace tumble::daemon
