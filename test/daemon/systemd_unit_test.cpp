// The shipped systemd files pass systemd's own checkers when they exist here.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "test/daemon/process.hpp"
#include "test/temp_dir.hpp"

namespace tumble::daemon {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = TUMBLE_SOURCE_DIR;
const std::string kTumbledBinary = std::string(TUMBLE_BINARY_DIR) + "/daemon/tumbled";

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string find_program(const std::string& name) {
  for (const char* dir : {"/usr/bin", "/bin", "/usr/sbin", "/sbin"}) {
    const fs::path candidate = fs::path(dir) / name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return {};
}

using tumble::test::TempDir;

TEST(SystemdUnit, HasTheAgreedSettings) {
  const std::string unit = read_file(kSource / "systemd/tumbled.service");
  for (const char* line :
       {"Type=notify", "NotifyAccess=main", "WatchdogSec=", "Restart=on-failure", "User=tumble", "NoNewPrivileges=yes",
        "ProtectSystem=strict", "ProtectHome=yes", "PrivateTmp=yes", "DevicePolicy=closed",
        "DeviceAllow=", "ReadWritePaths=/var/lib/tumble", "RestartPreventExitStatus=2", "LimitRTPRIO=20",
        "ExecStart=/usr/bin/tumbled --config /etc/tumble/tumbled.yaml", "MemoryHigh=512M", "MemoryMax=768M",
        "SystemCallFilter=@system-service", "ProtectProc=invisible", "ProcSubset=pid", "RemoveIPC=yes",
        "RestrictAddressFamilies=AF_UNIX AF_INET"}) {
    EXPECT_NE(unit.find(std::string("\n") + line), std::string::npos) << line;
  }
}

// The start limit is a [Unit] setting: in [Service] systemd would ignore it.
TEST(SystemdUnit, RestartsForeverWithoutAStartLimit) {
  const std::string unit = read_file(kSource / "systemd/tumbled.service");
  const std::size_t service = unit.find("\n[Service]");
  const std::size_t limit = unit.find("\nStartLimitIntervalSec=0\n");
  ASSERT_NE(service, std::string::npos);
  EXPECT_LT(limit, service) << "StartLimitIntervalSec=0 missing from [Unit]";
  EXPECT_NE(unit.find("\nRestart=on-failure\n", service), std::string::npos);
  EXPECT_NE(unit.find("\nRestartSec=5s\n", service), std::string::npos);
}

TEST(SystemdUnit, VerifiesCleanly) {
  const std::string analyze = find_program("systemd-analyze");
  if (analyze.empty()) GTEST_SKIP() << "systemd-analyze not installed (Debian package systemd)";
  // verify checks that ExecStart's binary exists: point it at the one just built.
  const TempDir dir;
  const std::string unit = std::regex_replace(read_file(kSource / "systemd/tumbled.service"),
                                              std::regex("ExecStart=/usr/bin/tumbled"), "ExecStart=" + kTumbledBinary);
  const fs::path copy = dir.path() / "tumbled.service";
  std::ofstream(copy) << unit;
  const test::ProcessResult r = test::run_process({analyze, "verify", copy.string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "") << "systemd-analyze verify warns";  // unknown keys only warn
}

// systemd's own rating of the sandbox: 10 is none, 0 the tightest.
TEST(SystemdUnit, SecurityExposureIsAtMostTwo) {
  const std::string analyze = find_program("systemd-analyze");
  if (analyze.empty()) GTEST_SKIP() << "systemd-analyze not installed (Debian package systemd)";
  const test::ProcessResult r = test::run_process(
      {analyze, "security", "--offline=true", "--no-pager", (kSource / "systemd/tumbled.service").string()});
  std::smatch overall;
  const std::string report = r.out + r.err;
  ASSERT_TRUE(std::regex_search(report, overall, std::regex(R"(Overall exposure level for tumbled\.service: ([0-9.]+))")))
      << report;
  EXPECT_LE(std::stod(overall[1].str()), 2.0) << report;
}

TEST(SystemdUnit, SysusersFileCreatesTheUser) {
  const std::string sysusers = find_program("systemd-sysusers");
  if (sysusers.empty()) GTEST_SKIP() << "systemd-sysusers not installed (Debian package systemd)";
  const TempDir root;
  const test::ProcessResult r = test::run_process(
      {sysusers, "--root=" + root.path().string(), "--dry-run", (kSource / "systemd/tumble.sysusers.conf").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE((r.out + r.err).find("Creating user 'tumble'"), std::string::npos) << r.out << r.err;
}

TEST(SystemdUnit, UdevRuleNamesTheSymlinkTheDocsUse) {
  const std::string rules = read_file(kSource / "systemd/99-tumble-mti.rules");
  EXPECT_NE(rules.find("SYMLINK+=\"xsens\""), std::string::npos);
  EXPECT_NE(read_file(kSource / "systemd/tumbled.service").find("/dev/xsens"), std::string::npos);
}

}  // namespace
}  // namespace tumble::daemon
