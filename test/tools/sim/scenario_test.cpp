// Scenario files: defaults, errors that name the key, name resolution, and
// the shipped scenarios.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test/tools/sim/sensor_test_support.hpp"
#include "tools/sim/motion_load.hpp"
#include "tools/sim/scenario.hpp"
#include "tools/sim/sim_run.hpp"

namespace tumble::sim {
namespace {

using test::TempDir;

Scenario parse(const std::string& text, const std::filesystem::path& base = ".") {
  return parse_scenario(YAML::Load(text), "s.yaml", base);
}

std::string scenario_error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const SimConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

constexpr const char* kMinimal = "scene: garage\nmotion: static\n";

TEST(Scenario, OnlySceneAndMotionAreRequiredAndDefaultsAreTheDatasheets) {
  const Scenario s = parse(kMinimal);
  EXPECT_EQ(s.scene_path, sim_data_dir("scenes") / "garage.yaml");
  EXPECT_EQ(s.motion_ref, "static");
  EXPECT_EQ(s.motion["type"].as<std::string>(), "static");
  EXPECT_EQ(s.seed, 1u);
  EXPECT_FALSE(s.duration_s);
  EXPECT_EQ(s.lidar.rpm, 600);
  EXPECT_DOUBLE_EQ(s.lidar.range_noise_m, 0.02);
  EXPECT_EQ(s.imu.rate_hz, 100);
  EXPECT_EQ(s.imu_link.baud, 115200);
  EXPECT_DOUBLE_EQ(s.imu.gyro_noise_density_deg_s_sqrt_hz, 0.03);
  EXPECT_DOUBLE_EQ(s.imu.accel_noise_density_ug_sqrt_hz, 60.0);
  EXPECT_DOUBLE_EQ(s.imu.gyro_range_deg_s, 450.0);
  EXPECT_DOUBLE_EQ(s.imu.accel_range_m_s2, 200.0);
  EXPECT_DOUBLE_EQ(s.ground_truth_rate_hz, 1000.0);
  EXPECT_EQ(s.epoch_ns, 1'622'030'400'000'000'000);  // 2021-05-26T12:00:00Z
  EXPECT_TRUE(s.T_LI.isApprox(Eigen::Isometry3d::Identity()));
}

TEST(Scenario, ErrorsNameTheFileTheKeyAndWhy) {
  EXPECT_EQ(scenario_error_of("motion: static\n"), "s.yaml: scene: missing");
  EXPECT_NE(scenario_error_of("scene: nowhere\nmotion: static\n").find("s.yaml: scene: no such scene"), std::string::npos);
  EXPECT_NE(scenario_error_of("scene: garage\n").find("s.yaml: motion: missing"), std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "lidar: {rpm: 700}\n").find("s.yaml: lidar.rpm: must be 300, 600 or 1200"),
            std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "lidar: {rmp: 600}\n").find("s.yaml: lidar.rmp: unknown key"),
            std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "speed: 3\n").find("s.yaml: speed: unknown key"), std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "imu: {rate_hz: 300}\n").find("s.yaml: imu.rate_hz: must divide 400"),
            std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "imu: {rate_hz: 400}\n").find("s.yaml: imu.baud: 115200 is too slow"),
            std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "imu: {number_format: double}\n").find("s.yaml: imu.number_format: must be"),
            std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "epoch_utc: yesterday\n").find("s.yaml: epoch_utc: must be like"),
            std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "seed: -3\n").find("s.yaml: seed: must be an unsigned integer"),
            std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "extrinsics: {T_LI: {translation_m: [1, 2]}}\n")
                .find("s.yaml: extrinsics.T_LI.translation_m: must be 3 numbers"),
            std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "extrinsics: {imu_time_offset_s: 1.5}\n")
                .find("s.yaml: extrinsics.imu_time_offset_s: must be in [-1, 1], got 1.5"),
            std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "lidar: {dropout_probability: 1.5}\n")
                .find("s.yaml: lidar.dropout_probability: must be in [0, 1], got 1.5"),
            std::string::npos);
}

TEST(Scenario, PathsResolveAgainstTheScenarioFolderAndMotionsMayBeInline) {
  TempDir dir;
  test::BoxRoom room;
  room.write(dir.path());
  std::ofstream(dir.path() / "run.yaml") << "scene: box_room.yaml\n"
                                            "motion: {type: static, duration_s: 2}\n"
                                            "duration_s: 0.5\n"
                                            "epoch_utc: 2024-02-29T23:59:59.25Z\n"
                                            "extrinsics: {T_LI: {translation_m: [0.1, 0, -0.1], rpy_deg: [0, 0, 90]}}\n"
                                            "imu: {rate_hz: 400, baud: 921600, clock_drift_ppm: -3.5}\n";
  const Scenario s = load_scenario(dir.path() / "run.yaml");
  EXPECT_EQ(s.source_name, "run.yaml");
  EXPECT_EQ(s.scene_path, dir.path() / "box_room.yaml");
  EXPECT_EQ(s.motion_ref, "inline");
  EXPECT_EQ(*s.duration_s, 0.5);
  EXPECT_EQ(s.epoch_ns, 1'709'251'199'250'000'000);
  EXPECT_NEAR((s.T_LI.linear() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-12);
  EXPECT_EQ(*s.imu_clock_drift_ppm, -3.5);
  const SimRun run(s);
  EXPECT_EQ(run.duration_s(), 0.5);
  EXPECT_EQ(run.imu_clock().drift_ppm, -3.5);
}

TEST(Scenario, ResolvedSettingsSurviveARoundTripThroughYaml) {
  const Scenario a = parse(std::string(kMinimal) +
                           "seed: 99\nmotion_seed: 5\nlidar: {rpm: 1200, range_noise_m: 0.01, difop_phase_s: 0.25}\n"
                           "imu: {rate_hz: 200, baud: 460800, number_format: fp1632, noise: false}\n"
                           "extrinsics: {T_LI: {translation_m: [0.1, -0.2, 0.3], rpy_deg: [5, -10, 170]}}\n");
  const Scenario b = parse_scenario(YAML::Load(YAML::Dump(scenario_to_yaml(a))), "again.yaml", ".");
  EXPECT_EQ(b.scene_path, a.scene_path);
  EXPECT_EQ(YAML::Dump(b.motion), YAML::Dump(a.motion));
  EXPECT_EQ(b.seed, 99u);
  EXPECT_EQ(*b.motion_seed, 5u);
  EXPECT_EQ(b.lidar.rpm, 1200);
  EXPECT_EQ(b.lidar.range_noise_m, 0.01);
  EXPECT_EQ(*b.difop_phase_s, 0.25);
  EXPECT_EQ(b.imu.rate_hz, 200);
  EXPECT_EQ(b.imu_link.number_format, mti::NumberFormat::Fp1632);
  EXPECT_FALSE(b.imu_noise);
  EXPECT_EQ(b.epoch_ns, a.epoch_ns);
  EXPECT_TRUE(b.T_LI.isApprox(a.T_LI, 1e-12));
}

TEST(Scenario, ErrorSourcesAreOffByDefaultAndSwitchedByKey) {
  const Scenario off = parse(kMinimal);
  EXPECT_FALSE(off.imu.scale_factor_error || off.imu.misalignment || off.imu.g_sensitivity || off.imu.temperature_drift ||
               off.imu.timestamp_jitter);
  EXPECT_FALSE(off.lidar.range_offset_error || off.lidar.intensity_range_bias || off.lidar.dark_surface_dropout ||
               off.lidar.cage_bars.enabled || off.lidar.mixed_pixels);
  // Files of runs without them carry none of their keys.
  const YAML::Node off_yaml = scenario_to_yaml(off);
  for (const char* key : {"scale_factor_error", "misalignment", "g_sensitivity", "temperature_drift", "timestamp_jitter"})
    EXPECT_FALSE(off_yaml["imu"][key]) << key;
  for (const char* key : {"range_offset_error", "intensity_range_bias", "dark_surface_dropout", "cage_bars",
                          "mixed_pixels", "beam_divergence_horizontal_mrad"})
    EXPECT_FALSE(off_yaml["lidar"][key]) << key;

  const Scenario on = parse(std::string(kMinimal) +
                            "imu: {scale_factor_error: true, gyro_scale_factor_sigma_pct: 0.5, misalignment: true, "
                            "g_sensitivity: true, temperature_drift: true, warm_up_time_constant_s: 60, "
                            "timestamp_jitter: true, timestamp_jitter_s: 0.0001}\n"
                            "lidar: {range_offset_error: true, range_offset_sigma_m: 0.02, intensity_range_bias: true, "
                            "dark_surface_dropout: true, cage_bars: {count: 6, cage_radius_m: 0.5}, mixed_pixels: true, "
                            "beam_divergence_vertical_mrad: 2}\n");
  EXPECT_TRUE(on.imu.scale_factor_error && on.imu.misalignment && on.imu.g_sensitivity && on.imu.temperature_drift &&
              on.imu.timestamp_jitter);
  EXPECT_DOUBLE_EQ(on.imu.gyro_scale_factor_sigma_pct, 0.5);
  EXPECT_DOUBLE_EQ(on.imu.accel_scale_factor_sigma_pct, 0.1);  // the datasheet default
  EXPECT_DOUBLE_EQ(on.imu.warm_up_time_constant_s, 60.0);
  EXPECT_DOUBLE_EQ(on.imu.timestamp_jitter_s, 0.0001);
  EXPECT_DOUBLE_EQ(on.lidar.range_offset_sigma_m, 0.02);
  EXPECT_TRUE(on.lidar.cage_bars.enabled);
  EXPECT_EQ(on.lidar.cage_bars.count, 6);
  EXPECT_TRUE(on.lidar.mixed_pixels);
  EXPECT_DOUBLE_EQ(on.lidar.beam_divergence_vertical_mrad, 2.0);
  EXPECT_DOUBLE_EQ(on.lidar.beam_divergence_horizontal_mrad, 3.0);
  const Scenario back = parse_scenario(scenario_to_yaml(on), "back.yaml", ".");
  EXPECT_EQ(YAML::Dump(scenario_to_yaml(back)), YAML::Dump(scenario_to_yaml(on)));

  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "imu: {scale_factor: true}\n").find("s.yaml: imu.scale_factor: unknown key"),
            std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "lidar: {cage_bars: {bars: 3}}\n")
                .find("s.yaml: lidar.cage_bars.bars: unknown key"),
            std::string::npos);
  EXPECT_NE(scenario_error_of(std::string(kMinimal) + "lidar: {cage_bars: {cage_radius_m: 0.1, bar_radius_m: 0.1}}\n")
                .find("s.yaml: lidar.cage_bars.bar_radius_m: must be below cage_radius_m"),
            std::string::npos);
}

TEST(Scenario, ShippedScenariosLoadAndTheDefaultStartsStillForASecond) {
  for (const auto& entry : std::filesystem::directory_iterator(sim_data_dir("scenarios"))) {
    SCOPED_TRACE(entry.path().string());
    const SimRun run(load_scenario(entry.path()));
    EXPECT_GE(run.duration_s(), 5.0);
  }
  const SimRun demo(load_scenario(default_scenario_path()));
  EXPECT_GE(demo.duration_s(), 10.0);
  EXPECT_LE(demo.duration_s(), 15.0);
  const MotionState start = demo.motion().at(0.0);
  for (double t = 0.0; t <= 1.0; t += 0.01) {
    const MotionState s = demo.motion().at(t);
    EXPECT_TRUE(s.T_wb.isApprox(start.T_wb, 1e-12)) << t;
    EXPECT_EQ(s.omega_b.norm(), 0.0) << t;
    EXPECT_EQ(s.v_w.norm(), 0.0) << t;
  }
  EXPECT_GT(demo.motion().at(5.0).omega_b.norm(), 5.0);  // it does roll
}

}  // namespace
}  // namespace tumble::sim
