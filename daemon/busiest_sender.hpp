// Without lidar.source_ip, which sender on the lidar ports is the lidar: the
// one that sent the most datagrams over the last one to two seconds (of
// arrival time). Another sensor sending to the same ports now and then is
// then foreign (counted and reported) instead of being decoded as lidar
// data from another place and time; a lidar replaced by one with another
// address is followed within two seconds.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

namespace tumble::daemon {

class BusiestSender {
 public:
  static constexpr double kWindow_s = 1.0;
  static constexpr std::size_t kTracked = 4;  // senders counted at once; the quietest makes room

  // One datagram from src_ip at arrival_s. Returns whether src_ip is now the
  // lidar; changed() tells whether that choice just moved to another sender.
  bool observe(std::uint32_t src_ip, double arrival_s);
  std::optional<std::uint32_t> lidar() const { return lidar_; }
  bool changed() const { return changed_; }

 private:
  struct Tally {
    std::uint32_t ip = 0;
    std::uint64_t current = 0;   // datagrams in the window under way
    std::uint64_t previous = 0;  // in the window before
    std::uint64_t total() const { return current + previous; }
  };

  std::array<Tally, kTracked> senders_{};
  std::size_t used_ = 0;
  bool started_ = false;
  double window_start_s_ = 0.0;
  std::optional<std::uint32_t> lidar_;
  bool changed_ = false;
};

}  // namespace tumble::daemon
