#include "daemon/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <system_error>
#include <utility>

namespace tumble::daemon {

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path)), partial_path_(path_ + ".partial"), file_(std::fopen(partial_path_.c_str(), "w")) {
  if (file_ == nullptr) throw std::system_error(errno, std::generic_category(), partial_path_);
}

AtomicFile::~AtomicFile() {
  if (file_ != nullptr) std::fclose(file_);
}

void AtomicFile::commit() {
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
