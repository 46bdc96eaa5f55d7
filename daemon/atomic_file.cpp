#include "daemon/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <system_error>
#include <utility>

namespace tumble::daemon {

namespace {

void sync_directory_of(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  const int fd = ::open(parent.empty() ? "." : parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) throw std::system_error(errno, std::generic_category(), "open the directory of " + path);
  const int synced = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  if (synced != 0) throw std::system_error(error, std::generic_category(), "sync the directory of " + path);
}

}  // namespace

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path)), partial_path_(path_ + ".partial"), file_(std::fopen(partial_path_.c_str(), "w")) {
  if (file_ == nullptr) throw std::system_error(errno, std::generic_category(), partial_path_);
}

AtomicFile::~AtomicFile() {
  if (file_ != nullptr) std::fclose(file_);
}

int AtomicFile::append_durably(std::string_view text) {
  if (file_ == nullptr) return EBADF;
  // Past stdio's buffer (anything written through get() goes first), so that
  // a failed write leaves nothing behind to be written later out of order.
  const int fd = ::fileno(file_);
  if (std::fflush(file_) != 0) {
    const int error = errno;
    std::clearerr(file_);
    return error;
  }
  // A write that fails part-way is cut back off: no half line in the file.
  const off_t start = ::lseek(fd, 0, SEEK_CUR);
  while (!text.empty()) {
    const ssize_t n = ::write(fd, text.data(), text.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : EIO;
      if (start >= 0 && ::ftruncate(fd, start) == 0) ::lseek(fd, start, SEEK_SET);
      return error;
    }
    text.remove_prefix(static_cast<std::size_t>(n));
  }
  return ::fdatasync(fd) == 0 ? 0 : errno;
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
  sync_directory_of(path_);
}

}  // namespace tumble::daemon
