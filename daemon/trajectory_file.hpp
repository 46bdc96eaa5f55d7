// --trajectory-out: the registered scan poses in TUM format, one line per
// scan: "t x y z qx qy qz qw" (seconds, metres, unit quaternion W <- L).
// Written to PATH.partial and renamed to PATH by commit(), so PATH never
// holds a half-written file, however tumbled stops.
#pragma once

#include <cstdio>
#include <string>

#include "daemon/lcm_publisher.hpp"

namespace tumble::daemon {

class TrajectoryFile : public RegistrationObserver {
 public:
  explicit TrajectoryFile(std::string path);  // throws std::system_error when PATH.partial cannot be created
  ~TrajectoryFile() override;                 // without commit(), PATH.partial stays for inspection
  TrajectoryFile(const TrajectoryFile&) = delete;
  TrajectoryFile& operator=(const TrajectoryFile&) = delete;

  void on_registration(const RegistrationRecord& registration) override;

  // Flushes, syncs and renames PATH.partial to PATH. Throws std::system_error.
  void commit();

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string partial_path_;
  std::FILE* file_;
};

}  // namespace tumble::daemon
