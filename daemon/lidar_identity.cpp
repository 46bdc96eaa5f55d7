#include "daemon/lidar_identity.hpp"

namespace tumble::daemon {

bool LidarIdentity::lock_on(std::uint32_t src_ip) {
  if (lidar_) return false;
  lidar_ = src_ip;
  return true;
}

}  // namespace tumble::daemon
