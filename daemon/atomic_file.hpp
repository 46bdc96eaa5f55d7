// An output file that never exists half-written: written to PATH.partial and
// renamed to PATH by commit(), however the process stops. After a power cut,
// PATH.partial holds what append_durably() last made durable.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace tumble::daemon {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path);  // throws std::system_error when PATH.partial cannot be created
  ~AtomicFile();                          // without commit(), PATH.partial stays for inspection
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Null once committed.
  std::FILE* get() const { return file_; }
  // Writes text and flushes it to the disk (fdatasync): 0, or the errno of
  // the write or sync that failed. The file's error state is cleared, so a
  // later call (the disk has room again) can succeed.
  int append_durably(std::string_view text);
  // Flushes, syncs and renames PATH.partial to PATH, then syncs the directory
  // so that the rename itself survives a power cut. Throws std::system_error.
  void commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string partial_path_;
  std::FILE* file_;
};

}  // namespace tumble::daemon
