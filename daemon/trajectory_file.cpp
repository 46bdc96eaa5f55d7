#include "daemon/trajectory_file.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <system_error>
#include <utility>

namespace tumble::daemon {

TrajectoryFile::TrajectoryFile(std::string path)
    : path_(std::move(path)), partial_path_(path_ + ".partial"), file_(std::fopen(partial_path_.c_str(), "w")) {
  if (file_ == nullptr) throw std::system_error(errno, std::generic_category(), partial_path_);
}

TrajectoryFile::~TrajectoryFile() {
  if (file_ != nullptr) std::fclose(file_);
}

void TrajectoryFile::on_registration(const RegistrationRecord& r) {
  if (file_ == nullptr) return;  // committed
  const auto& q = r.orientation_wxyz;
  fmt::print(file_, "{:.6f} {:.6f} {:.6f} {:.6f} {:.9f} {:.9f} {:.9f} {:.9f}\n", r.t_s, r.position_m[0],
             r.position_m[1], r.position_m[2], q[1], q[2], q[3], q[0]);
}

void TrajectoryFile::commit() {
  if (file_ == nullptr) return;
  const bool written = std::fflush(file_) == 0 && ::fsync(::fileno(file_)) == 0;
  const int error = errno;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!written || !closed) throw std::system_error(error, std::generic_category(), partial_path_);
  if (std::rename(partial_path_.c_str(), path_.c_str()) != 0)
    throw std::system_error(errno, std::generic_category(), "rename to " + path_);
}

}  // namespace tumble::daemon
