// The optional tumble-view.service passes systemd's checker where it exists
// here, and keeps the view on loopback, read-only and bounded.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "test/daemon/process.hpp"
#include "test/temp_dir.hpp"

namespace tumble::view {
namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

const std::string kUnit = read_file(fs::path(TUMBLE_SOURCE_DIR) / "systemd/tumble-view.service");

TEST(ViewService, ListensOnLoopbackAsAnUnprivilegedBoundedService) {
  for (const char* line : {"ExecStart=/usr/bin/tumble-view --listen 127.0.0.1:8076", "DynamicUser=yes",
                           "NoNewPrivileges=yes", "ProtectSystem=strict", "CapabilityBoundingSet=", "MemoryMax=",
                           "Restart=on-failure", "RestartPreventExitStatus=2"})
    EXPECT_NE(kUnit.find(std::string("\n") + line), std::string::npos) << line;
}

TEST(ViewService, VerifiesCleanly) {
  const std::string analyze = "/usr/bin/systemd-analyze";
  if (::access(analyze.c_str(), X_OK) != 0) GTEST_SKIP() << "systemd-analyze not installed (Debian package systemd)";
  // verify checks that ExecStart's binary exists: point it at the one just built.
  const test::TempDir dir;
  const fs::path copy = dir.path() / "tumble-view.service";
  std::ofstream(copy) << std::regex_replace(kUnit, std::regex("ExecStart=/usr/bin/tumble-view"),
                                            std::string("ExecStart=") + TUMBLE_BINARY_DIR + "/tools/view/tumble-view");
  const test::ProcessResult r = test::run_process({analyze, "verify", copy.string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "") << "systemd-analyze verify warns";
}

}  // namespace
}  // namespace tumble::view
