#include "daemon/driver_params.hpp"

#include <gtest/gtest.h>

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

TEST(ScanAssemblerConfigFromConfig, MinScanCoverageReachesTheAssembler) {
  EXPECT_DOUBLE_EQ(scan_assembler_config(LidarConfig{}).min_scan_coverage, 0.9);
  const DaemonConfig config = load_config("lidar:\n  min_scan_coverage: 0.5\n  split_azimuth_deg: 90\n", "test.yaml");
  const rs16::ScanAssemblerConfig scans = scan_assembler_config(config.lidar);
  EXPECT_DOUBLE_EQ(scans.min_scan_coverage, 0.5);
  EXPECT_DOUBLE_EQ(scans.split_azimuth_deg, 90.0);
}

}  // namespace
}  // namespace tumble::daemon
