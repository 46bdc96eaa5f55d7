// A unique scratch folder under the system temp dir, removed with everything
// in it: tests running in parallel (ctest -j) never share one.
#pragma once

#include <filesystem>
#include <random>
#include <string>
#include <system_error>

namespace tumble::test {

class TempDir {
 public:
  explicit TempDir(const std::string& tag = "test") {
    std::random_device random;
    path_ = std::filesystem::temp_directory_path() /
            ("tumble-" + tag + "-" + std::to_string(random()) + "-" + std::to_string(random()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace tumble::test
