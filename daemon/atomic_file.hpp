// An output file that never exists half-written: written to PATH.partial and
// renamed to PATH by commit(), however the process stops.
#pragma once

#include <cstdio>
#include <string>

namespace tumble::daemon {

class AtomicFile {
 public:
  explicit AtomicFile(std::string path);  // throws std::system_error when PATH.partial cannot be created
  ~AtomicFile();                          // without commit(), PATH.partial stays for inspection
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  // Null once committed.
  std::FILE* get() const { return file_; }
  // Flushes, syncs and renames PATH.partial to PATH. Throws std::system_error.
  void commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::string partial_path_;
  std::FILE* file_;
};

}  // namespace tumble::daemon
