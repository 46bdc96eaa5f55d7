// tumbled as a command: exit codes, one-line errors, --print-config.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "daemon/config.hpp"
#include "test/daemon/process.hpp"
#include "tumble_build_info.hpp"

namespace tumble::daemon {
namespace {

namespace fs = std::filesystem;

const std::string kTumbled = std::string(TUMBLE_BINARY_DIR) + "/daemon/tumbled";

class TempYaml {
 public:
  explicit TempYaml(const std::string& text)
      : path_(fs::temp_directory_path() / ("tumble_bin_" + std::to_string(::getpid()) + ".yaml")) {
    std::ofstream(path_) << text;
  }
  ~TempYaml() { fs::remove(path_); }
  std::string path() const { return path_.string(); }

 private:
  fs::path path_;
};

TEST(TumbledBinary, PrintConfigRoundTrips) {
  const test::ProcessResult r = test::run_process({kTumbled, "--print-config"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(load_config(r.out, "printed"), DaemonConfig{});
  const test::ProcessResult shipped = test::run_process(
      {kTumbled, "--config", std::string(TUMBLE_SOURCE_DIR) + "/config/tumbled.yaml", "--print-config"});
  EXPECT_EQ(shipped.out, r.out);
}

TEST(TumbledBinary, PrintConfigShowsCommandLineOverrides) {
  const TempYaml file("registration:\n  model: NM\n");
  const test::ProcessResult r =
      test::run_process({kTumbled, "--config", file.path(), "--model", "SAW", "--no-deskew", "--print-config"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const DaemonConfig printed = load_config(r.out, "printed");
  EXPECT_EQ(printed.registration.model, WeightModel::SAW);
  EXPECT_FALSE(printed.registration.deskew);
}

TEST(TumbledBinary, BadConfigExitsTwoWithOneLineNamingTheKey) {
  const TempYaml file("registration:\n  voxel_size_m: 0\n");
  const test::ProcessResult r = test::run_process({kTumbled, "--config", file.path()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tumbled: registration.voxel_size_m: 0 is out of range (0.005..1)\n");
  EXPECT_TRUE(r.out.empty());
}

TEST(TumbledBinary, UsageErrorsExitTwo) {
  EXPECT_EQ(test::run_process({kTumbled, "--no-such-flag"}).exit_code, 2);
  EXPECT_EQ(test::run_process({kTumbled, "--model", "XYZ"}).exit_code, 2);
  const test::ProcessResult r = test::run_process({kTumbled, "--rate", "max"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(TumbledBinary, HelpExitsZeroAndNamesTheSystemConfiguration) {
  const test::ProcessResult r = test::run_process({kTumbled, "--help"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--trajectory-out"), std::string::npos);
  EXPECT_NE(r.out.find(std::string("default: ") + kSystemConfigPath + " where it exists"), std::string::npos) << r.out;
}

// help2man reads the program's name and version from the first line.
TEST(TumbledBinary, VersionIsTheProjectVersion) {
  const test::ProcessResult r = test::run_process({kTumbled, "--version"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out, std::string("tumbled ") + kVersion + "\n");
}

}  // namespace
}  // namespace tumble::daemon
