#include "core/scan_line_normals.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "core/voxel_grid.hpp"
#include "test/core/synthetic_room.hpp"

namespace tumble {
namespace {

std::vector<std::uint32_t> all_of(const PointCloud& cloud) {
  std::vector<std::uint32_t> indices(cloud.size());
  std::iota(indices.begin(), indices.end(), std::uint32_t{0});
  return indices;
}

LidarPoint lidar_point(std::uint8_t laser, double x, double y, double z) {
  LidarPoint p;
  p.laser = laser;
  p.x_m = static_cast<float>(x);
  p.y_m = static_cast<float>(y);
  p.z_m = static_cast<float>(z);
  return p;
}

TEST(RingElevations, FromTheFirstReturnOfEachLaserAndInfiniteForSilentOnes) {
  Scan scan;
  scan.points = {lidar_point(2, 1, 0, 1), lidar_point(0, 3, 4, -5), lidar_point(2, 1, 0, -1)};
  std::vector<double> elevations{9, 9, 9, 9, 9, 9};
  ring_elevations_rad(scan, elevations);
  ASSERT_EQ(elevations.size(), 3u);
  EXPECT_NEAR(elevations[0], -M_PI / 4, 1e-7);  // from float coordinates
  EXPECT_EQ(elevations[1], std::numeric_limits<double>::infinity());
  EXPECT_NEAR(elevations[2], M_PI / 4, 1e-7);
}

TEST(ScanLineNormals, RoomNormalsAreTheFaceNormals) {
  // The room is a box with boxes in it: every surface is axis-aligned.
  const std::vector<LidarPoint> raw = test::scan_room(test::make_room(), [](double) { return Eigen::Isometry3d::Identity(); },
                                                      0.0, test::RingLidar{.columns = test::full_or_coarse(900, 300)});
  PointCloud cloud;
  VoxelDownsampler(0.05).apply(test::to_cloud(raw), cloud);
  Scan scan;
  scan.points = raw;
  std::vector<double> elevations;
  ring_elevations_rad(scan, elevations);
  ScanLineNormals normals(NormalParams{}, ScanLineWindow{});
  normals.index(cloud, elevations);
  normals.estimate(cloud, Eigen::Vector3d::Zero(), all_of(cloud));
  std::size_t valid = 0, axis_aligned = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_NEAR(cloud.normals[i].norm(), 1.0, 1e-9);
    EXPECT_GE(cloud.normals[i].dot(-cloud.points[i]), 0.0) << "faces the sensor";
    if (!cloud.normal_valid[i]) continue;
    ++valid;
    if (cloud.normals[i].cwiseAbs().maxCoeff() > std::cos(5 * M_PI / 180)) ++axis_aligned;
  }
  // The rest straddle an edge within the curvature limit. Measured: 99 % valid,
  // 87 % of them within 5 deg (k-nearest normals of the same cloud: 99 %, 90 %:
  // a window two rings high reaches farther across an edge); coarse builds'
  // sparser scan: 84 %.
  EXPECT_GT(valid, cloud.size() * 95 / 100);
  EXPECT_GT(axis_aligned, valid * test::full_or_coarse(85, 80) / 100);
}

// A wall 5 m ahead seen by 16 lasers numbered as on the RS-16: 0..7 upward
// from -15 deg, then 8..15 downward from +15 deg, 2 deg apart. Laser 7 (-1 deg)
// has lasers 6 and 15 beside it in elevation, but 8 (+15 deg) beside it in
// number, 1.4 m away on the wall.
PointCloud wall_of_interleaved_lasers(std::vector<double>& elevations) {
  PointCloud cloud;
  elevations.assign(16, 0.0);
  for (int laser = 0; laser < 16; ++laser) {
    const double elevation_deg = laser < 8 ? -15 + 2 * laser : 15 - 2 * (laser - 8);
    elevations[static_cast<std::size_t>(laser)] = elevation_deg * M_PI / 180;
  }
  for (int column = 0; column < 60; ++column) {
    const double azimuth = (-6 + 0.2 * column) * M_PI / 180;
    for (int laser = 0; laser < 16; ++laser) {
      const double e = elevations[static_cast<std::size_t>(laser)];
      const Eigen::Vector3d dir(std::cos(e) * std::cos(azimuth), std::cos(e) * std::sin(azimuth), std::sin(e));
      const std::size_t i = cloud.size();
      cloud.resize(i + 1);
      cloud.points[i] = dir * (5.0 / dir.x());
      cloud.times_s[i] = 1e-4 * column + 2e-6 * laser;
      cloud.rings[i] = static_cast<std::uint8_t>(laser);
    }
  }
  return cloud;
}

TEST(ScanLineNormals, NeighbouringRingsAreNeighboursInElevationNotInNumber) {
  std::vector<double> elevations;
  PointCloud cloud = wall_of_interleaved_lasers(elevations);
  NormalParams params;
  // Only a point with both rings beside it (11 + 11 points) passes; one ring gives 11.
  params.min_other_line_neighbours = 15;
  ScanLineNormals normals(params, ScanLineWindow{.points_each_side = 5, .rings_each_side = 1});
  normals.index(cloud, elevations);
  normals.estimate(cloud, Eigen::Vector3d::Zero(), all_of(cloud));
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const std::uint8_t laser = cloud.rings[i];
    const std::size_t column = i / 16;
    if (laser == 0 || laser == 8 || column < 5 || column >= 55) continue;  // the wall's edges: one ring beside
    ASSERT_TRUE(cloud.normal_valid[i]) << "laser " << int(laser) << " column " << column;
    EXPECT_NEAR(cloud.normals[i].x(), -1.0, 1e-9);
  }
}

TEST(ScanLineNormals, ARingWithNoOtherRingNearbyHasNoNormal) {
  std::vector<double> elevations;
  PointCloud cloud = wall_of_interleaved_lasers(elevations);
  NormalParams params;
  params.max_radius_m = 0.1;  // the rings are 17 cm apart on the wall
  ScanLineNormals normals(params, ScanLineWindow{});
  normals.index(cloud, elevations);
  const std::vector<std::uint32_t> some{100, 200, 300};
  normals.estimate(cloud, Eigen::Vector3d::Zero(), some);
  for (const std::uint32_t i : some) {
    EXPECT_FALSE(cloud.normal_valid[i]);
    EXPECT_NEAR(cloud.normals[i].dot(-cloud.points[i].normalized()), 1.0, 1e-12) << "faces the sensor";
  }
}

TEST(ScanLineNormals, RejectsAnEmptyWindow) {
  EXPECT_THROW(ScanLineNormals(NormalParams{}, ScanLineWindow{.points_each_side = 0}), std::invalid_argument);
  EXPECT_THROW(ScanLineNormals(NormalParams{}, ScanLineWindow{.rings_each_side = 0}), std::invalid_argument);
}

TEST(ScanLineNormals, RejectsMoreRingsThanItIndexes) {
  EXPECT_NO_THROW(ScanLineNormals(NormalParams{}, ScanLineWindow{.rings_each_side = ScanLineNormals::kMaxRingsEachSide}));
  EXPECT_THROW(ScanLineNormals(NormalParams{}, ScanLineWindow{.rings_each_side = ScanLineNormals::kMaxRingsEachSide + 1}),
               std::invalid_argument);
}

}  // namespace
}  // namespace tumble
