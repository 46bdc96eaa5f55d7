// Scratch folders and file writing for the tumble-calib tests.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "test/temp_dir.hpp"

namespace tumble::calib::test {

using tumble::test::TempDir;

inline void write_file(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace tumble::calib::test
