#include "core/voxel_grid.hpp"

#include <gtest/gtest.h>

#include <random>

#include "test/core/synthetic_room.hpp"

namespace tumble {
namespace {

PointCloud numbered_cloud_of(const std::vector<Eigen::Vector3d>& points) {
  PointCloud c;
  c.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    c.points[i] = points[i];
    c.times_s[i] = 100.0 + static_cast<double>(i);
    c.sigma_s_m[i] = 0.01 * static_cast<double>(i);
    c.weights[i] = 1.0 / (1.0 + static_cast<double>(i));
  }
  return c;
}

TEST(VoxelDownsampler, KeepsThePointNearestTheCellCentreWithItsAttributes) {
  // Cell [0, 0.1)^3 has centre (0.05, 0.05, 0.05); point 2 is nearest it.
  const PointCloud in = numbered_cloud_of({{0.01, 0.01, 0.01}, {0.09, 0.02, 0.05}, {0.06, 0.04, 0.05}, {0.099, 0.099, 0.099}});
  VoxelDownsampler grid(0.1);
  PointCloud out;
  grid.apply(in, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out.points[0], in.points[2]);
  EXPECT_EQ(out.times_s[0], in.times_s[2]);
  EXPECT_EQ(out.sigma_s_m[0], in.sigma_s_m[2]);
  EXPECT_EQ(out.weights[0], in.weights[2]);
}

TEST(VoxelDownsampler, OnePointPerOccupiedCellInFirstSeenOrder) {
  // Negative coordinates must fall in their own cells (floor, not truncation).
  const PointCloud in = numbered_cloud_of({{0.5, 0.5, 0.5}, {-0.01, 0.02, 0.03}, {0.52, 0.55, 0.51}, {0.01, 0.02, 0.03}});
  VoxelDownsampler grid(0.1);
  PointCloud out;
  grid.apply(in, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out.points[0], in.points[2]);  // nearer (0.55, 0.55, 0.55) than point 0
  EXPECT_EQ(out.points[1], in.points[1]);
  EXPECT_EQ(out.points[2], in.points[3]);
}

TEST(VoxelDownsampler, DeterministicAndReusable) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-5, 5);
  std::vector<Eigen::Vector3d> pts(test::full_or_coarse(5000, 800));
  for (auto& p : pts) p = Eigen::Vector3d(u(rng), u(rng), u(rng));
  const PointCloud in = numbered_cloud_of(pts);
  VoxelDownsampler grid(0.5);
  PointCloud a, b;
  grid.apply(in, a);
  grid.apply(numbered_cloud_of({{0, 0, 0}}), b);  // a different cloud in between
  EXPECT_EQ(b.size(), 1u);
  grid.apply(in, b);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a.points[i], b.points[i]);
  // A grid whose cell table first served one point grows it for many.
  VoxelDownsampler grown(0.5);
  PointCloud c;
  grown.apply(numbered_cloud_of({{0, 0, 0}}), c);
  grown.apply(in, c);
  ASSERT_EQ(a.size(), c.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a.points[i], c.points[i]);
  // Every output point is the nearest to its cell's centre among the input.
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector3d cell = (a.points[i] / 0.5).array().floor();
    const Eigen::Vector3d centre = (cell + Eigen::Vector3d::Constant(0.5)) * 0.5;
    for (const auto& p : pts) {
      if ((p / 0.5).array().floor().matrix() == cell) {
        EXPECT_GE((p - centre).norm(), (a.points[i] - centre).norm());
      }
    }
  }
}

TEST(VoxelDownsampler, SelectGivesTheIndicesApplyKeeps) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-2, 2);
  PointCloud in;
  in.resize(3000);
  for (std::size_t i = 0; i < in.size(); ++i) {
    in.points[i] = Eigen::Vector3d(u(rng), u(rng), u(rng));
    in.times_s[i] = static_cast<double>(i);
  }
  VoxelDownsampler grid(0.3);
  PointCloud out;
  grid.apply(in, out);
  std::vector<std::uint32_t> indices;
  grid.select(in.points, indices);
  ASSERT_EQ(indices.size(), out.size());
  for (std::size_t j = 0; j < indices.size(); ++j) EXPECT_EQ(in.points[indices[j]], out.points[j]);
}

TEST(VoxelDownsampler, RejectsNonPositiveSize) {
  EXPECT_THROW(VoxelDownsampler(0.0), std::invalid_argument);
  EXPECT_THROW(VoxelDownsampler(-1.0), std::invalid_argument);
}

}  // namespace
}  // namespace tumble
