// Who the lidar is, for the whole run. With lidar.source_ip, that address.
// Without it, the first address that sends a well-formed MSOP datagram to
// the lidar's port, never another until a restart: a second host sending
// well-formed RS-16 traffic (another robot's lidar, a forgotten replay)
// must never take the lidar's place, however fast it sends. Choosing by
// traffic (the busiest sender) would let such a host become the lidar within
// seconds.
#pragma once

#include <cstdint>
#include <optional>

namespace tumble::daemon {

class LidarIdentity {
 public:
  explicit LidarIdentity(std::optional<std::uint32_t> configured_ip) : lidar_(configured_ip) {}

  // Whether a datagram from src_ip may be the lidar's: before the lock, anyone's.
  bool may_be_lidar(std::uint32_t src_ip) const { return !lidar_ || *lidar_ == src_ip; }
  // A well-formed MSOP datagram came from src_ip: the first one locks. True when this call locked.
  bool lock_on(std::uint32_t src_ip);
  std::optional<std::uint32_t> lidar() const { return lidar_; }

 private:
  std::optional<std::uint32_t> lidar_;
};

}  // namespace tumble::daemon
