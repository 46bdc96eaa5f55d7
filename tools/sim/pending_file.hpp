// A file written under a temporary name and renamed when complete, so a run
// folder never holds a truncated file under a final name.
#pragma once

#include <filesystem>
#include <system_error>
#include <utility>

namespace tumble::sim {

class PendingFile {
 public:
  explicit PendingFile(std::filesystem::path final_path)
      : final_(std::move(final_path)), temp_(final_.string() + ".tmp") {}
  ~PendingFile() {
    std::error_code ignored;
    if (!committed_) std::filesystem::remove(temp_, ignored);
  }
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;
  const std::filesystem::path& temp() const { return temp_; }
  void commit() {
    std::filesystem::rename(temp_, final_);
    committed_ = true;
  }

 private:
  std::filesystem::path final_, temp_;
  bool committed_ = false;
};

}  // namespace tumble::sim
