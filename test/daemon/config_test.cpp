#include "daemon/config.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "daemon/command_line.hpp"

namespace tumble::daemon {
namespace {

const std::string kShippedConfig = std::string(TUMBLE_SOURCE_DIR) + "/config/tumbled.yaml";

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The ConfigError message for yaml, or "" when it loads.
std::string error_of(const std::string& yaml) {
  try {
    load_config(yaml, "test.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, ShippedFileEqualsCompiledDefaults) {
  const DaemonConfig shipped = load_config_file(kShippedConfig);
  EXPECT_EQ(shipped, DaemonConfig{}) << "config/tumbled.yaml and daemon/config.hpp disagree:\n"
                                     << to_yaml(shipped) << "\nvs\n"
                                     << to_yaml(DaemonConfig{});
}

TEST(Config, ShippedFileListsEveryKey) {
  // Every key the printer emits appears in the shipped file (documented in place).
  const std::string shipped = read_file(kShippedConfig);
  std::istringstream printed(to_yaml(DaemonConfig{}));
  for (std::string line; std::getline(printed, line);) {
    const std::string key = line.substr(0, line.find(':'));
    EXPECT_NE(shipped.find(key + ":"), std::string::npos) << key;
  }
}

// The leaf keys of to_yaml's output as dotted paths (two spaces of indent per level).
std::vector<std::string> printed_key_paths(const DaemonConfig& config) {
  std::vector<std::string> keys, path;
  std::istringstream printed(to_yaml(config));
  for (std::string line; std::getline(printed, line);) {
    const std::size_t indent = line.find_first_not_of(' ');
    const std::size_t colon = line.find(':');
    if (indent == std::string::npos || colon == std::string::npos) continue;
    path.resize(indent / 2);
    const std::string name = line.substr(indent, colon - indent);
    if (line.find_first_not_of(' ', colon + 1) == std::string::npos) {
      path.push_back(name);  // a section
    } else {
      std::string key;
      for (const std::string& part : path) key += part + ".";
      keys.push_back(key + name);
    }
  }
  return keys;
}

std::vector<std::string> sorted_keys(std::vector<std::string> keys) {
  std::sort(keys.begin(), keys.end());
  return keys;
}

TEST(Config, KeysAreEveryKeyThePrinterWritesOnce) {
  DaemonConfig quaternion;
  quaternion.imu.extrinsic_T_LI.rotation_rpy_deg.reset();
  quaternion.imu.extrinsic_T_LI.rotation_quaternion_wxyz = std::array<double, 4>{1.0, 0.0, 0.0, 0.0};
  std::vector<std::string> printed = printed_key_paths(DaemonConfig{});
  printed.push_back("imu.extrinsic_T_LI.rotation_quaternion_wxyz");
  EXPECT_EQ(sorted_keys(config_keys()), sorted_keys(printed));
  const std::vector<std::string> with_quaternion = printed_key_paths(quaternion);
  EXPECT_NE(std::find(with_quaternion.begin(), with_quaternion.end(), "imu.extrinsic_T_LI.rotation_quaternion_wxyz"),
            with_quaternion.end());
}

TEST(Config, ConfigurationDocListsExactlyTheSchemasKeys) {
  // docs/configuration.md documents each key in a table row that starts with it: | `lidar.msop_port` | ...
  const std::string page = read_file(std::string(TUMBLE_SOURCE_DIR) + "/docs/configuration.md");
  ASSERT_FALSE(page.empty());
  std::vector<std::string> documented;
  const std::regex row(R"(\n\| `([A-Za-z0-9_.]+)` \|)");
  for (auto it = std::sregex_iterator(page.begin(), page.end(), row); it != std::sregex_iterator(); ++it)
    documented.push_back((*it)[1].str());
  const std::vector<std::string> doc = sorted_keys(documented), schema = sorted_keys(config_keys());
  std::vector<std::string> undocumented, unknown;
  std::set_difference(schema.begin(), schema.end(), doc.begin(), doc.end(), std::back_inserter(undocumented));
  std::set_difference(doc.begin(), doc.end(), schema.begin(), schema.end(), std::back_inserter(unknown));
  EXPECT_TRUE(undocumented.empty()) << "keys of daemon/config.cpp's schema missing from docs/configuration.md: "
                                    << ::testing::PrintToString(undocumented);
  EXPECT_TRUE(unknown.empty()) << "keys in docs/configuration.md that the schema does not have: "
                               << ::testing::PrintToString(unknown);
  EXPECT_EQ(doc.size(), schema.size()) << "a key is documented twice";
}

TEST(Config, DefaultsAreThePaperValues) {
  const DaemonConfig c;
  EXPECT_EQ(c.registration.model, WeightModel::GVTW);
  EXPECT_TRUE(c.registration.deskew);
  EXPECT_EQ(c.registration.voxel_size_m, 0.05);
  EXPECT_EQ(c.registration.frmsd_min_ratio, 0.5);
  EXPECT_EQ(c.registration.frmsd_max_ratio, 0.7);
  EXPECT_EQ(c.registration.frmsd_lambda, 2.35);
  EXPECT_EQ(c.registration.max_iterations, 40);
  EXPECT_EQ(c.registration.lognormal_beta, 1.1);
  EXPECT_EQ(c.registration.lognormal_kappa_m_s, 1.9);
  EXPECT_EQ(c.registration.lognormal_lambda, 0.222);
  EXPECT_EQ(c.registration.cubic_phi_rad_s, 16.0);
  EXPECT_EQ(c.registration.tw_c1_m_s, 0.25);
  EXPECT_EQ(c.registration.vtw_c2, 2.0);
  EXPECT_EQ(c.registration.gvtw_c3, 4.0);
  EXPECT_EQ(c.fuser.madgwick_beta, 0.1);
  EXPECT_EQ(c.fuser.accel_correction_after_s, 0.5);  // ours (README, "The attitude between scans")
  EXPECT_EQ(c.fuser.levelling_max_expected_error_m, 0.024);
  EXPECT_EQ(c.fuser.levelling_max_rotation_error_deg, 0.15);
  EXPECT_EQ(c.map.radius_m, 50.0);
  EXPECT_EQ(c.lcm.url, "udpm://239.255.76.67:7667?ttl=0");
  EXPECT_EQ(c.lcm.channel_prefix, "TUMBLE_");
  EXPECT_NO_THROW(validate(c));
}

TEST(Config, PrintedConfigLoadsBackEqual) {
  DaemonConfig c;
  c.registration.model = WeightModel::SAW;
  c.registration.frmsd_lambda = 0.1 + 0.2;  // not exactly representable in short decimal
  c.lidar.vertical_angles_deg = {-15, -13, -11, -9, -7, -5, -3, -1, 15, 13, 11, 9, 7, 5, 3, 1};
  c.lidar.source_ip = "192.168.1.200";
  c.imu.extrinsic_T_LI.rotation_rpy_deg.reset();
  c.imu.extrinsic_T_LI.rotation_quaternion_wxyz = std::array<double, 4>{0.0, 0.0, 0.0, 1.0};
  c.record.dir = "/var/lib/tumble/\"quoted\" dir";
  c.daemon.health.min_degeneracy = 1e-7;
  ASSERT_NO_THROW(validate(c));
  EXPECT_EQ(load_config(to_yaml(c), "printed"), c);
}

TEST(Config, MissingKeysKeepDefaults) {
  const DaemonConfig c = load_config("registration:\n  model: NM\n", "partial.yaml");
  DaemonConfig expected;
  expected.registration.model = WeightModel::NM;
  EXPECT_EQ(c, expected);
  EXPECT_EQ(load_config("", "empty.yaml"), DaemonConfig{});
}

TEST(Config, ChoicesIgnoreCase) {
  EXPECT_EQ(load_config("registration:\n  model: gvtw\n", "x").registration.model, WeightModel::GVTW);
  EXPECT_EQ(load_config("lidar:\n  clock: SYNCED\n", "x").lidar.clock, LidarClock::Synced);
}

TEST(ConfigErrors, OutOfRangeNamesKeyAndRange) {
  EXPECT_EQ(error_of("registration:\n  voxel_size_m: 0\n"), "registration.voxel_size_m: 0 is out of range (0.005..1)");
  EXPECT_EQ(error_of("lidar:\n  msop_port: 70000\n"), "lidar.msop_port: 70000 is out of range (1..65535)");
  EXPECT_EQ(error_of("lidar:\n  min_scan_coverage: 1.2\n"), "lidar.min_scan_coverage: 1.2 is out of range (0..1)");
  EXPECT_EQ(error_of("daemon:\n  health:\n    min_matched_ratio: 1.5\n"),
            "daemon.health.min_matched_ratio: 1.5 is out of range (0..1)");
  EXPECT_EQ(error_of("imu:\n  extrinsic_T_LI:\n    translation_m: [0, 11, 0]\n"),
            "imu.extrinsic_T_LI.translation_m[1]: 11 is out of range (-10..10)");
  EXPECT_EQ(error_of("registration:\n  voxel_size_m: .nan\n"),
            "registration.voxel_size_m: expected a number, got \".nan\"");
  EXPECT_EQ(error_of("imu:\n  baud: 12345\n"),
            "imu.baud: 12345 is not one of 9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600, 2000000");
}

TEST(Config, OutputFileKeysLoadAndAreRangeChecked) {
  const DaemonConfig c = load_config(
      "daemon:\n  checkpoint_period_s: 0.5\nrecord:\n  max_segment_mib: 64\n  max_segment_s: 30\n  min_free_mib: 0\n",
      "test.yaml");
  EXPECT_DOUBLE_EQ(c.daemon.checkpoint_period_s, 0.5);
  EXPECT_EQ(c.record.max_segment_mib, 64);
  EXPECT_DOUBLE_EQ(c.record.max_segment_s, 30.0);
  EXPECT_EQ(c.record.min_free_mib, 0);
  EXPECT_EQ(error_of("daemon:\n  checkpoint_period_s: 0\n"),
            "daemon.checkpoint_period_s: 0 is out of range (0.1..60)");
  EXPECT_EQ(error_of("record:\n  max_segment_mib: 0\n"), "record.max_segment_mib: 0 is out of range (1..1048576)");
  EXPECT_EQ(error_of("record:\n  max_segment_s: 0.5\n"), "record.max_segment_s: 0.5 is out of range (1..86400)");
  EXPECT_EQ(error_of("record:\n  min_free_mib: -1\n"), "record.min_free_mib: -1 is out of range (0..1048576)");
}

TEST(ConfigErrors, WrongTypeNamesKeyAndExpectedType) {
  EXPECT_EQ(error_of("lidar:\n  msop_port: abc\n"), "lidar.msop_port: expected an integer, got \"abc\"");
  EXPECT_EQ(error_of("lidar:\n  msop_port: 6699.5\n"), "lidar.msop_port: expected an integer, got \"6699.5\"");
  EXPECT_EQ(error_of("registration:\n  deskew: yes\n"), "registration.deskew: expected true or false, got \"yes\"");
  EXPECT_EQ(error_of("registration:\n  voxel_size_m: [1]\n"),
            "registration.voxel_size_m: expected a number, got a list");
  EXPECT_EQ(error_of("imu:\n  extrinsic_T_LI:\n    translation_m: [0, 0]\n"),
            "imu.extrinsic_T_LI.translation_m: expected a list of 3 numbers, got 2 values");
  EXPECT_EQ(error_of("registration:\n  model: XYZ\n"),
            "registration.model: \"XYZ\" is not one of NM, TW, VTW, GVTW, SAW");
  EXPECT_EQ(error_of("lidar: 5\n"), "lidar: expected a mapping of keys, got \"5\"");
  EXPECT_EQ(error_of("- a\n- b\n"), "test.yaml: expected a mapping of sections (lidar, imu, ...), got a list");
  EXPECT_EQ(error_of("lidar:\n  source_ip: 300.1.2.3\n"),
            "lidar.source_ip: \"300.1.2.3\" is not an IPv4 address (like 192.168.1.200) or empty");
  EXPECT_EQ(error_of("lcm:\n  url: localhost\n"),
            "lcm.url: \"localhost\" is not an LCM URL (provider://network?options, e.g. "
            "udpm://239.255.76.67:7667?ttl=0)");
}

TEST(ConfigErrors, UnknownAndDuplicateKeysAreNamed) {
  const std::string unknown = error_of("registration:\n  voxel_size: 0.05\n");
  EXPECT_EQ(unknown.rfind("registration.voxel_size: unknown key (known here: model, deskew, voxel_size_m,", 0), 0u)
      << unknown;
  EXPECT_EQ(error_of("lidars:\n  msop_port: 1\n").rfind("lidars: unknown key (known here: lidar, imu,", 0), 0u);
  EXPECT_EQ(error_of("lidar:\n  msop_port: 1\n  msop_port: 2\n"), "lidar.msop_port: duplicate key");
}

TEST(ConfigErrors, InconsistentPairsNameBothKeys) {
  EXPECT_EQ(error_of("registration:\n  frmsd_min_ratio: 0.8\n"),
            "registration.frmsd_min_ratio: 0.8 must not exceed registration.frmsd_max_ratio (0.7)");
  EXPECT_EQ(error_of("lidar:\n  min_range_m: 250\n"), "lidar.min_range_m: 250 must be below lidar.max_range_m (200)");
  EXPECT_EQ(error_of("lidar:\n  difop_port: 6699\n"), "lidar.difop_port: 6699 must differ from lidar.msop_port");
  EXPECT_EQ(error_of("imu:\n  rate_hz: 400\n"), "imu.rate_hz: 400 Hz needs at least 432000 baud, imu.baud is 115200");
  EXPECT_EQ(error_of("imu:\n  rate_hz: 400\n  baud: 460800\n"), "");
  EXPECT_EQ(error_of("imu:\n  rate_hz: 800\n  configure: false\n"), "");
  EXPECT_EQ(error_of("imu:\n  extrinsic_T_LI:\n    rotation_rpy_deg: [0, 0, 0]\n"
                     "    rotation_quaternion_wxyz: [1, 0, 0, 0]\n"),
            "imu.extrinsic_T_LI: give either rotation_rpy_deg or rotation_quaternion_wxyz, not both");
  EXPECT_EQ(error_of("imu:\n  extrinsic_T_LI:\n    rotation_quaternion_wxyz: [0.5, 0, 0, 0]\n"),
            "imu.extrinsic_T_LI.rotation_quaternion_wxyz: norm 0.5 is not 1 (+-0.01)");
  EXPECT_EQ(error_of("lidar:\n  vertical_angles_deg: [1, 2]\n"),
            "lidar.vertical_angles_deg: has 2 values; give none (use the lidar's own) or exactly 16");
}

TEST(ConfigErrors, AreOneLine) {
  for (const char* yaml : {"registration:\n  voxel_size_m: 0\n", "lidar: [\n", "a: b: c\n", "x:\n  - [\n"}) {
    const std::string message = error_of(yaml);
    EXPECT_FALSE(message.empty()) << yaml;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_EQ(error_of("lidar: [\n").rfind("test.yaml:", 0), 0u);  // syntax errors name file:line:column
}

TEST(ConfigErrors, ValidateCatchesValuesSetInCode) {
  DaemonConfig c;
  c.map.radius_m = 0;
  try {
    validate(c);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "map.radius_m: 0 is out of range (1..1000)");
  }
}

TEST(Config, MissingFileIsAConfigError) { EXPECT_THROW(load_config_file("/nonexistent/tumbled.yaml"), ConfigError); }

TEST(Config, OverridesWinOverTheFileAndAreValidated) {
  const std::vector<ConfigOverride> overrides = {{"registration.model", "TW"}, {"lcm.url", "memq://"}};
  const DaemonConfig c = load_config("registration:\n  model: NM\n  deskew: false\n", "f.yaml", overrides);
  EXPECT_EQ(c.registration.model, WeightModel::TW);
  EXPECT_FALSE(c.registration.deskew);  // from the file
  EXPECT_EQ(c.lcm.url, "memq://");
  const std::vector<ConfigOverride> bad = {{"registration.model", "nope"}};
  EXPECT_THROW(default_config(bad), ConfigError);
  const std::vector<ConfigOverride> nested = {{"daemon.health.sensor_timeout_s", "2"}};
  EXPECT_EQ(default_config(nested).daemon.health.sensor_timeout_s, 2.0);
}

TEST(Config, AnOverrideCanBeAList) {
  const std::vector<ConfigOverride> list = {{"imu.extrinsic_T_LI.translation_m", "[0.02, 0, -0.08]"}};
  EXPECT_EQ(default_config(list).imu.extrinsic_T_LI.translation_m, (std::array<double, 3>{0.02, 0.0, -0.08}));
  const std::vector<ConfigOverride> broken = {{"imu.extrinsic_T_LI.translation_m", "[0.02, 0"}};
  try {
    default_config(broken);
    FAIL() << "no ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("imu.extrinsic_T_LI.translation_m: [0.02, 0 is not a YAML list"),
              std::string::npos)
        << e.what();
  }
}

TEST(Config, ExtrinsicFromRollPitchYaw) {
  ExtrinsicConfig e;
  e.translation_m = {0.1, 0.2, 0.3};
  e.rotation_rpy_deg = std::array<double, 3>{0.0, 0.0, 90.0};
  const Eigen::Isometry3d T = extrinsic_T_LI(e);
  EXPECT_TRUE((T * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(0.1, 1.2, 0.3), 1e-12));
  e.rotation_rpy_deg.reset();
  e.rotation_quaternion_wxyz = std::array<double, 4>{std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)};
  EXPECT_TRUE(extrinsic_T_LI(e).isApprox(T, 1e-12));
}

}  // namespace
}  // namespace tumble::daemon
