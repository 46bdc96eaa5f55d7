#include "daemon/command_line.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "test/temp_dir.hpp"

namespace tumble::daemon {
namespace {

namespace fs = std::filesystem;

// A file that exists for the test's duration (CLI11 checks --config and --replay paths).
class TempFile {
 public:
  explicit TempFile(const std::string& text) {
    path_ = fs::temp_directory_path() /
            ("tumble_cli_" + std::to_string(::getpid()) + "_" + std::to_string(counter_++) + ".yaml");
    std::ofstream(path_) << text;
  }
  ~TempFile() { fs::remove(path_); }
  std::string path() const { return path_.string(); }

 private:
  static inline int counter_ = 0;
  fs::path path_;
};

CommandLine parse(std::vector<std::string> args) {
  args.insert(args.begin(), "tumbled");
  return parse_command_line(args);
}

TEST(CommandLine, NoFlagsMeansLiveWithDefaults) {
  const CommandLine c = parse({});
  EXPECT_FALSE(c.config_path);
  EXPECT_FALSE(c.replay);
  EXPECT_TRUE(c.overrides.empty());
  EXPECT_EQ(effective_config(c), DaemonConfig{});
}

// A temp dir stands in for the system configuration folder (/etc/tumble).
TEST(CommandLine, WithoutConfigTheSystemFileIsReadWhereItExists) {
  const test::TempDir etc("system-config");
  const fs::path system_file = etc.path() / "tumbled.yaml";
  CommandLine absent = parse({});
  use_system_config_unless_given(absent, system_file);
  EXPECT_FALSE(absent.config_path);
  EXPECT_EQ(config_origin(absent), "compiled defaults");
  EXPECT_EQ(effective_config(absent), DaemonConfig{});

  std::ofstream(system_file) << "registration:\n  model: TW\n";
  CommandLine present = parse({"--log-level", "warn"});
  use_system_config_unless_given(present, system_file);
  EXPECT_EQ(config_origin(present), system_file.string());
  const DaemonConfig config = effective_config(present);
  EXPECT_EQ(config.registration.model, WeightModel::TW);
  EXPECT_EQ(config.daemon.log_level, LogLevel::Warn);
}

TEST(CommandLine, AGivenConfigWinsOverTheSystemFile) {
  const test::TempDir etc("system-config");
  const fs::path system_file = etc.path() / "tumbled.yaml";
  std::ofstream(system_file) << "registration:\n  model: TW\n";
  const TempFile given("registration:\n  model: SAW\n");
  CommandLine c = parse({"--config", given.path()});
  use_system_config_unless_given(c, system_file);
  EXPECT_EQ(config_origin(c), given.path());
  EXPECT_EQ(effective_config(c).registration.model, WeightModel::SAW);
}

TEST(CommandLine, FlagsOverrideTheConfigFile) {
  const TempFile file(
      "registration:\n  model: NM\n  deskew: true\nlcm:\n  url: \"udpm://239.255.76.67:7667?ttl=1\"\n"
      "daemon:\n  log_level: debug\n");
  const CommandLine c = parse({"--config", file.path(), "--model", "VTW", "--no-deskew", "--lcm-url", "memq://",
                               "--log-level", "warn", "--record", "/tmp/rec"});
  const DaemonConfig config = effective_config(c);
  EXPECT_EQ(config.registration.model, WeightModel::VTW);
  EXPECT_FALSE(config.registration.deskew);
  EXPECT_EQ(config.lcm.url, "memq://");
  EXPECT_EQ(config.daemon.log_level, LogLevel::Warn);
  EXPECT_EQ(config.record.dir, "/tmp/rec");
  // Keys no flag touches come from the file.
  const CommandLine only_file = parse({"--config", file.path()});
  EXPECT_EQ(effective_config(only_file).registration.model, WeightModel::NM);
  EXPECT_EQ(effective_config(only_file).daemon.log_level, LogLevel::Debug);
}

TEST(CommandLine, DeskewFlagTurnsItOn) {
  const TempFile file("registration:\n  deskew: false\n");
  EXPECT_TRUE(effective_config(parse({"--config", file.path(), "--deskew"})).registration.deskew);
  EXPECT_THROW(parse({"--deskew", "--no-deskew"}), UsageError);
}

TEST(CommandLine, BadFlagValuesAreConfigErrorsNamingTheKey) {
  try {
    effective_config(parse({"--model", "XYZ"}));
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "registration.model: \"XYZ\" is not one of NM, TW, VTW, GVTW, SAW");
  }
  EXPECT_THROW(effective_config(parse({"--log-level", "loud"})), ConfigError);
}

TEST(CommandLine, ReplayTakesTwoFilesAndARate) {
  const TempFile lidar("x"), imu("y");
  const CommandLine c =
      parse({"--replay", lidar.path(), imu.path(), "--rate", "max", "--trajectory-out", "/tmp/t.tum"});
  ASSERT_TRUE(c.replay);
  EXPECT_EQ(c.replay->lidar_pcap, lidar.path());
  EXPECT_EQ(c.replay->imu_pcap, imu.path());
  EXPECT_TRUE(c.rate.max);
  EXPECT_EQ(c.trajectory_out, "/tmp/t.tum");
  EXPECT_EQ(parse({"--replay", lidar.path(), imu.path(), "--rate", "4"}).rate, (ReplayRate{false, 4.0}));
  EXPECT_EQ(parse({"--replay", lidar.path(), imu.path()}).rate, (ReplayRate{false, 1.0}));
}

TEST(CommandLine, UsageErrors) {
  const TempFile lidar("x");
  EXPECT_THROW(parse({"--replay", lidar.path()}), UsageError);                  // one file
  EXPECT_THROW(parse({"--replay", lidar.path(), "/nonexistent"}), UsageError);  // missing file
  EXPECT_THROW(parse({"--rate", "max"}), UsageError);                           // without --replay
  EXPECT_THROW(parse({"--replay", lidar.path(), lidar.path(), "--rate", "0"}), UsageError);
  EXPECT_THROW(parse({"--replay", lidar.path(), lidar.path(), "--rate", "fast"}), UsageError);
  EXPECT_THROW(parse({"--config", "/nonexistent.yaml"}), UsageError);
  EXPECT_THROW(parse({"--frobnicate"}), UsageError);
  EXPECT_THROW(parse({"--replay", lidar.path(), lidar.path(), "--record", "/tmp"}), UsageError);
}

TEST(CommandLine, HelpIsNotAnError) {
  const CommandLine c = parse({"--help"});
  EXPECT_NE(c.help.find("--replay"), std::string::npos);
  EXPECT_NE(c.help.find("--print-config"), std::string::npos);
}

TEST(CommandLine, ReplayRateParsing) {
  EXPECT_TRUE(parse_replay_rate("max").max);
  EXPECT_EQ(parse_replay_rate("0.5").factor, 0.5);
  EXPECT_THROW(parse_replay_rate("-1"), UsageError);
  EXPECT_THROW(parse_replay_rate("inf"), UsageError);
  EXPECT_THROW(parse_replay_rate("2x"), UsageError);
}

}  // namespace
}  // namespace tumble::daemon
