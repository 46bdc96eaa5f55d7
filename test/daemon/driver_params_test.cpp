#include "daemon/driver_params.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace tumble::daemon {
namespace {

TEST(OdometryParamsFromConfig, ReadingNormalsKeysReachTheCore) {
  const OdometryParams defaults = odometry_params(DaemonConfig{});
  EXPECT_EQ(defaults.reading_normal_source, ReadingNormalSource::kScanLines);
  EXPECT_EQ(defaults.reading_normals.k, 15);

  const DaemonConfig config = load_config(
      "registration:\n  reading_normals: knn\n  scan_line_points_each_side: 7\n"
      "  scan_line_rings_each_side: 3\n  normal_k_reading: 12\n",
      "test.yaml");
  const OdometryParams p = odometry_params(config);
  EXPECT_EQ(p.reading_normal_source, ReadingNormalSource::kNearest);
  EXPECT_EQ(p.scan_line_window.points_each_side, 7);
  EXPECT_EQ(p.scan_line_window.rings_each_side, 3);
  EXPECT_EQ(p.reading_normals.k, 12);
}

TEST(OdometryParamsFromConfig, SeenThroughKeysReachTheCore) {
  const OdometryParams defaults = odometry_params(DaemonConfig{});
  EXPECT_TRUE(defaults.seen_through.enabled);
  EXPECT_DOUBLE_EQ(defaults.seen_through.beam_radius_m, SeenThroughParams{}.beam_radius_m);
  EXPECT_DOUBLE_EQ(defaults.seen_through.margin_m, SeenThroughParams{}.margin_m);
  EXPECT_DOUBLE_EQ(defaults.seen_through.max_range_m, SeenThroughParams{}.max_range_m);
  EXPECT_DOUBLE_EQ(defaults.seen_through.max_expected_error_m, SeenThroughParams{}.max_expected_error_m);
  EXPECT_EQ(defaults.seen_through.beam_stride, SeenThroughParams{}.beam_stride);

  const DaemonConfig config = load_config(
      "map:\n  remove_seen_through: false\n  seen_through_beam_radius_m: 0.07\n  seen_through_margin_m: 0.8\n"
      "  seen_through_max_range_m: 12\n  seen_through_max_expected_error_m: 0.05\n"
      "  seen_through_beam_stride: 3\n",
      "test.yaml");
  const OdometryParams p = odometry_params(config);
  EXPECT_FALSE(p.seen_through.enabled);
  EXPECT_DOUBLE_EQ(p.seen_through.beam_radius_m, 0.07);
  EXPECT_DOUBLE_EQ(p.seen_through.margin_m, 0.8);
  EXPECT_DOUBLE_EQ(p.seen_through.max_range_m, 12.0);
  EXPECT_DOUBLE_EQ(p.seen_through.max_expected_error_m, 0.05);
  EXPECT_EQ(p.seen_through.beam_stride, 3u);
  EXPECT_THROW(load_config("map:\n  seen_through_beam_radius_m: 0\n", "test.yaml"), ConfigError);
}

TEST(OdometryParamsFromConfig, UnobservedDirectionKeysReachTheCore) {
  const OdometryParams defaults = odometry_params(DaemonConfig{});
  EXPECT_DOUBLE_EQ(defaults.unobserved.weak_min_eigenvalue, UnobservedDirectionParams{}.weak_min_eigenvalue);
  EXPECT_EQ(defaults.unobserved.window_scans, UnobservedDirectionParams{}.window_scans);
  EXPECT_DOUBLE_EQ(defaults.unobserved.enter_fraction, UnobservedDirectionParams{}.enter_fraction);
  EXPECT_DOUBLE_EQ(defaults.unobserved.sigma_m, UnobservedDirectionParams{}.sigma_m);

  const DaemonConfig config = load_config(
      "registration:\n  unobserved_min_eigenvalue: 0.003\n  unobserved_window_scans: 12\n"
      "  unobserved_fraction: 0.75\n  unobserved_sigma_m: 5\n",
      "test.yaml");
  const OdometryParams p = odometry_params(config);
  EXPECT_DOUBLE_EQ(p.unobserved.weak_min_eigenvalue, 0.003);
  EXPECT_EQ(p.unobserved.window_scans, 12u);
  EXPECT_DOUBLE_EQ(p.unobserved.enter_fraction, 0.75);
  EXPECT_DOUBLE_EQ(p.unobserved.sigma_m, 5.0);
  EXPECT_THROW(load_config("registration:\n  unobserved_window_scans: 0\n", "test.yaml"), ConfigError);
  EXPECT_THROW(load_config("registration:\n  unobserved_sigma_m: 0\n", "test.yaml"), ConfigError);
}

TEST(OdometryParamsFromConfig, AWeakScanHoldsItsTranslationAtTheWeakScansThreshold) {
  // One threshold for both: a weak scan (unobserved_min_eigenvalue) is one
  // that holds; what it leaves unmeasured is as uncertain as an unobserved direction.
  const OdometryParams defaults = odometry_params(DaemonConfig{});
  EXPECT_DOUBLE_EQ(defaults.icp.hold_weak_translation_share, 0.002);
  EXPECT_DOUBLE_EQ(defaults.fuser.unmeasured_position_sigma_m, 1.0);
  const OdometryParams p = odometry_params(
      load_config("registration:\n  unobserved_min_eigenvalue: 0.003\n  unobserved_sigma_m: 5\n", "test.yaml"));
  EXPECT_DOUBLE_EQ(p.icp.hold_weak_translation_share, 0.003);
  EXPECT_DOUBLE_EQ(p.fuser.unmeasured_position_sigma_m, 5.0);
  const OdometryParams off =
      odometry_params(load_config("registration:\n  hold_weak_translation: false\n", "test.yaml"));
  EXPECT_DOUBLE_EQ(off.icp.hold_weak_translation_share, 0.0);
  EXPECT_THROW(load_config("registration:\n  hold_weak_translation: maybe\n", "test.yaml"), ConfigError);
}

TEST(OdometryParamsFromConfig, ThePredictionIsICPsPriorByDefaultAndZeroTurnsItOff) {
  EXPECT_DOUBLE_EQ(odometry_params(DaemonConfig{}).position.prediction_sigma_m, 0.02);
  EXPECT_DOUBLE_EQ(OdometryParams{}.position.prediction_sigma_m, 0.0);  // the core's: the paper's ICP
  const OdometryParams off = odometry_params(load_config("registration:\n  prediction_sigma_m: 0\n", "test.yaml"));
  EXPECT_DOUBLE_EQ(off.position.prediction_sigma_m, 0.0);
  EXPECT_THROW(load_config("registration:\n  prediction_sigma_m: -0.01\n", "test.yaml"), ConfigError);
}

TEST(OdometryParamsFromConfig, JumpsAreTestedAt5SigmaAndALossWaitsForHalfASecondAtRest) {
  const OdometryParams defaults = odometry_params(DaemonConfig{});
  EXPECT_DOUBLE_EQ(defaults.position.jump_sigmas, 5.0);
  EXPECT_DOUBLE_EQ(OdometryParams{}.position.jump_sigmas, 0.0);  // the core's: no prediction to jump from
  EXPECT_DOUBLE_EQ(defaults.fuser.rest_duration_s, 0.5);
  EXPECT_EQ(defaults.fuser.rest_duration_s, ImuFuserParams{}.rest_duration_s);
  const OdometryParams set =
      odometry_params(load_config("registration:\n  jump_sigmas: 0\nfuser:\n  rest_static_s: 2\n", "test.yaml"));
  EXPECT_DOUBLE_EQ(set.position.jump_sigmas, 0.0);
  EXPECT_DOUBLE_EQ(set.fuser.rest_duration_s, 2.0);
  EXPECT_THROW(load_config("registration:\n  jump_sigmas: -1\n", "test.yaml"), ConfigError);
  EXPECT_THROW(load_config("fuser:\n  rest_static_s: 61\n", "test.yaml"), ConfigError);
}

TEST(OdometryParamsFromConfig, TheLevellingsAttitudeLimitReachesTheFuserInRadians) {
  EXPECT_NEAR(odometry_params(DaemonConfig{}).fuser.levelling_max_rotation_error_rad, 0.15 * std::numbers::pi / 180.0,
              1e-15);
  EXPECT_EQ(odometry_params(DaemonConfig{}).fuser.levelling_max_rotation_error_rad,
            ImuFuserParams{}.levelling_max_rotation_error_rad);  // the core's default is the config's
  const OdometryParams wide =
      odometry_params(load_config("fuser:\n  levelling_max_rotation_error_deg: 2\n", "test.yaml"));
  EXPECT_NEAR(wide.fuser.levelling_max_rotation_error_rad, 2.0 * std::numbers::pi / 180.0, 1e-15);
  EXPECT_THROW(load_config("fuser:\n  levelling_max_rotation_error_deg: -1\n", "test.yaml"), ConfigError);
}

TEST(ScanAssemblerConfigFromConfig, MinScanCoverageReachesTheAssembler) {
  EXPECT_DOUBLE_EQ(scan_assembler_config(LidarConfig{}).min_scan_coverage, 0.9);
  const DaemonConfig config = load_config("lidar:\n  min_scan_coverage: 0.5\n  split_azimuth_deg: 90\n", "test.yaml");
  const rs16::ScanAssemblerConfig scans = scan_assembler_config(config.lidar);
  EXPECT_DOUBLE_EQ(scans.min_scan_coverage, 0.5);
  EXPECT_DOUBLE_EQ(scans.split_azimuth_deg, 90.0);
}

TEST(ImuLimitsFromConfig, TheDevicesRangesReachTheSampleCheckInRadians) {
  const ImuLimits defaults = imu_limits(ImuConfig{});
  EXPECT_NEAR(defaults.gyro_range_rad_s, 7.854, 1e-3);  // MTi-30 G4: 450 deg/s
  EXPECT_DOUBLE_EQ(defaults.accel_range_m_s2, 200.0);
  const DaemonConfig config = load_config("imu:\n  gyro_range_deg_s: 1000\n  accel_range_m_s2: 50\n", "test.yaml");
  const ImuLimits l = imu_limits(config.imu);
  EXPECT_DOUBLE_EQ(l.gyro_range_rad_s, 1000.0 * std::numbers::pi / 180.0);
  EXPECT_DOUBLE_EQ(l.accel_range_m_s2, 50.0);
}

TEST(LidarDecoderConfigFromConfig, FollowingDifopChangesIsOffByDefaultAndReachesTheDecoder) {
  EXPECT_FALSE(lidar_decoder_config(LidarConfig{}).follow_difop_changes);
  const DaemonConfig config = load_config("lidar:\n  follow_difop_changes: true\n", "test.yaml");
  EXPECT_TRUE(lidar_decoder_config(config.lidar).follow_difop_changes);
}

TEST(HealthKeysFromConfig, TheSecondLidarRateAndTheScanTimeoutLoadIntoTheHealthLimits) {
  const DaemonConfig config = load_config(
      "daemon:\n  health:\n    second_lidar_rate_hz: 100\n    scan_timeout_s: 0.8\n", "test.yaml");
  EXPECT_DOUBLE_EQ(config.daemon.health.second_lidar_rate_hz, 100.0);
  EXPECT_DOUBLE_EQ(config.daemon.health.scan_timeout_s, 0.8);
  EXPECT_THROW(load_config("daemon:\n  health:\n    scan_timeout_s: 0\n", "test.yaml"), ConfigError);
}

}  // namespace
}  // namespace tumble::daemon
