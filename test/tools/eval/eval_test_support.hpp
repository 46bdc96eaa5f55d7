// Shared by the tumble-eval tests: a temporary folder removed afterwards, and
// small file writers.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "test/temp_dir.hpp"

namespace tumble::eval::test {

using tumble::test::TempDir;

inline void write_file(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace tumble::eval::test
