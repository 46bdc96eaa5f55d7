// --trajectory-out: the registered scan poses in TUM format, one line per
// registered scan: "t x y z qx qy qz qw" (seconds, metres, unit quaternion
// W <- L). Scans the registration could not place are left out.
#pragma once

#include <string>

#include "daemon/atomic_file.hpp"
#include "daemon/lcm_publisher.hpp"

namespace tumble::daemon {

class TrajectoryFile : public RegistrationObserver {
 public:
  explicit TrajectoryFile(std::string path) : file_(std::move(path)) {}

  void on_registration(const RegistrationRecord& registration) override;
  void commit() { file_.commit(); }
  const std::string& path() const { return file_.path(); }

 private:
  AtomicFile file_;
};

}  // namespace tumble::daemon
