// Where the shared sensor fixtures are, and a skip with a clear message when a
// clone has none (they live outside the repository).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace tumble::test {

inline std::filesystem::path fixture_path(const std::string& relative) {
  return std::filesystem::path(TUMBLE_FIXTURES_DIR) / relative;
}

}  // namespace tumble::test

// Skips the calling test unless the fixture exists.
#define TUMBLE_REQUIRE_FIXTURE(relative)                                                  \
  do {                                                                                   \
    if (!std::filesystem::exists(::tumble::test::fixture_path(relative)))                 \
      GTEST_SKIP() << "fixture " << (relative) << " not found under " TUMBLE_FIXTURES_DIR \
                   << " (set -DTUMBLE_FIXTURES_DIR=...)";                                 \
  } while (0)
