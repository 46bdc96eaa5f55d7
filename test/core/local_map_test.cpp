#include "core/local_map.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "test/core/cloud_of.hpp"
#include "test/core/synthetic_room.hpp"

namespace tumble {
namespace {

using test::cloud_of;

TEST(LocalMap, NewPointNeedsMinimumDistanceToEveryMapPoint) {
  LocalMap map(LocalMapParams{.min_point_distance_m = 0.05});
  EXPECT_EQ(map.insert(cloud_of({{1, 1, 1}}), Eigen::Isometry3d::Identity()).inserted, 1u);
  // 2-3 cm away, across a voxel border (voxel 0.25 m): still too close.
  const MapInsertStats close = map.insert(cloud_of({{1, 1, 0.98}, {1, 0.97, 1}}), Eigen::Isometry3d::Identity());
  EXPECT_EQ(close.inserted, 0u);
  EXPECT_EQ(close.rejected_too_close, 2u);
  // 7 cm away: far enough; the same rule holds among the points of one insert.
  const MapInsertStats far = map.insert(cloud_of({{1, 1, 1.07}, {1, 1, 1.1}, {1, 1, 1.2}}), Eigen::Isometry3d::Identity());
  EXPECT_EQ(far.inserted, 2u);
  EXPECT_EQ(far.rejected_too_close, 1u);
  EXPECT_EQ(map.size(), 3u);
}

TEST(LocalMap, InsertsInTheWorldFrameOfThePose) {
  LocalMap map;
  Eigen::Isometry3d T_wl = test::make_pose(Eigen::Vector3d(10, -5, 2), 0, 0, M_PI / 2);
  map.insert(cloud_of({{1, 0, 0}}), T_wl);
  Neighbour nn;
  ASSERT_EQ(map.knn(Eigen::Vector3d(10, -4, 2), 0.01, std::span<Neighbour>(&nn, 1)), 1u);
  EXPECT_NEAR(map.position(nn.index).x(), 10, 1e-12);
  EXPECT_NEAR(map.position(nn.index).y(), -4, 1e-12);
}

TEST(LocalMap, PointsTooUncertainStayOut) {
  LocalMap map(LocalMapParams{.max_sigma_s_m = 1.0});
  PointCloud c = cloud_of({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}});
  c.sigma_s_m = {0.5, 1.0, 1.5, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()};
  const MapInsertStats stats = map.insert(c, Eigen::Isometry3d::Identity());
  EXPECT_EQ(stats.inserted, 2u);
  EXPECT_EQ(stats.rejected_sigma, 3u);
  std::vector<double> variances;
  map.for_each_point([&](const Eigen::Vector3d&, const MapPoint& p) { variances.push_back(p.variance_m2); });
  std::sort(variances.begin(), variances.end());
  const double sigma_n = c.sigma_n_m[0];
  EXPECT_EQ(variances, (std::vector<double>{sigma_n * sigma_n + 0.25, sigma_n * sigma_n + 1.0}));
}

TEST(LocalMap, VoxelCapBoundsPointsPerVoxel) {
  LocalMap map(LocalMapParams{.voxel_size_m = 1.0, .max_points_per_voxel = 5, .min_point_distance_m = 0.05});
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 9; ++i) pts.emplace_back(0.1 * i + 0.05, 0.5, 0.5);
  const MapInsertStats stats = map.insert(cloud_of(pts), Eigen::Isometry3d::Identity());
  EXPECT_EQ(stats.inserted, 5u);
  EXPECT_EQ(stats.rejected_voxel_full, 4u);
  EXPECT_EQ(map.voxel_count(), 1u);
}

TEST(LocalMap, RemovesExactlyTheVoxelsOutsideTheRadius) {
  LocalMapParams params{.voxel_size_m = 0.5, .radius_m = 10};
  LocalMap map(params);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-20, 20);
  std::vector<Eigen::Vector3d> pts(test::full_or_coarse(4000, 1000));
  for (auto& p : pts) p = Eigen::Vector3d(u(rng), u(rng), u(rng) * 0.1);
  map.insert(cloud_of(pts), Eigen::Isometry3d::Identity());
  const std::size_t before = map.size();
  const Eigen::Vector3d centre(3, -2, 0);
  std::size_t expected_kept = 0;
  map.for_each_point([&](const Eigen::Vector3d& p_w, const MapPoint&) {
    const Eigen::Vector3d cell = (p_w / 0.5).array().floor();
    if (((cell + Eigen::Vector3d::Constant(0.5)) * 0.5 - centre).norm() <= 10) ++expected_kept;
  });
  const std::size_t removed = map.remove_far_from(centre);
  EXPECT_EQ(map.size(), expected_kept);
  EXPECT_EQ(removed, before - expected_kept);
  EXPECT_GT(removed, 0u);
  map.for_each_point([&](const Eigen::Vector3d& p_w, const MapPoint&) { EXPECT_LT((p_w - centre).norm(), 10 + 0.5 * std::sqrt(3.0)); });
  // Freed voxels are reused: a re-insert restores the far points.
  map.insert(cloud_of(pts), Eigen::Isometry3d::Identity());
  EXPECT_EQ(map.size(), before);
}

TEST(LocalMap, RemovedPointsGoAndEveryOtherPointKeepsItsData) {
  // Voxels of 1 m hold 1 to 40 points over 3 chunks; some lose a few, one all.
  LocalMap map(LocalMapParams{.voxel_size_m = 1.0, .min_point_distance_m = 0.0});
  std::vector<Eigen::Vector3d> pts;
  for (int v = 0; v < 4; ++v)
    for (int i = 0; i < (v == 3 ? 1 : 40); ++i) pts.emplace_back(v + 0.02 * i + 0.01, 0.5, 0.5);
  PointCloud cloud = cloud_of(pts);
  for (std::size_t i = 0; i < pts.size(); ++i) cloud.sigma_s_m[i] = 0.001 * static_cast<double>(i);
  ASSERT_EQ(map.insert(cloud, Eigen::Isometry3d::Identity()).inserted, pts.size());
  auto index_at = [&](const Eigen::Vector3d& p) {
    Neighbour nn;
    EXPECT_EQ(map.knn(p, 1e-6, std::span<Neighbour>(&nn, 1)), 1u);
    return nn.index;
  };
  // Voxel 0: its first, a middle and its last point; voxel 1: every point
  // but one (twice over: duplicates count once); voxel 2: all 40, over 3
  // chunks; voxel 3: its only point.
  std::vector<Eigen::Vector3d> doomed_points{pts[0], pts[17], pts[39], pts[120]};
  for (int i = 40; i < 79; ++i) doomed_points.push_back(pts[static_cast<std::size_t>(i)]);
  for (int i = 80; i < 120; ++i) doomed_points.push_back(pts[static_cast<std::size_t>(i)]);
  std::vector<std::uint32_t> doomed;
  for (const auto& p : doomed_points) doomed.push_back(index_at(p));
  doomed.push_back(doomed.back());
  EXPECT_EQ(map.remove_points(doomed), doomed_points.size());
  EXPECT_EQ(map.size(), pts.size() - doomed_points.size());
  EXPECT_EQ(map.voxel_count(), 2u);
  std::vector<std::pair<double, double>> kept;  // x and the σ it went in with
  map.for_each_point([&](const Eigen::Vector3d& p_w, const MapPoint& p) { kept.emplace_back(p_w.x(), p.variance_m2); });
  std::sort(kept.begin(), kept.end());
  std::vector<std::pair<double, double>> expected;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (std::find(doomed_points.begin(), doomed_points.end(), pts[i]) != doomed_points.end()) continue;
    expected.emplace_back(pts[i].x(), cloud.sigma_n_m[i] * cloud.sigma_n_m[i] + cloud.sigma_s_m[i] * cloud.sigma_s_m[i]);
  }
  EXPECT_EQ(kept, expected);
  for (const auto& [x, variance] : expected) EXPECT_DOUBLE_EQ(map.position(index_at({x, 0.5, 0.5})).x(), x);
  // A box search sees exactly the points left (the voxels' bounds shrank with them).
  for (int v = 0; v < 4; ++v) {
    std::vector<double> in_box;
    map.for_each_point_in_cell(CellKey{v, 0, 0}, Eigen::Vector3d(v + 0.1, 0.4, 0.4), Eigen::Vector3d(v + 0.8, 0.6, 0.6),
                               [&](std::uint32_t, const Eigen::Vector3d& p) { in_box.push_back(p.x()); });
    std::sort(in_box.begin(), in_box.end());
    std::vector<double> expected_in_box;
    for (const auto& [x, variance] : expected)
      if (x >= v + 0.1 && x <= v + 0.8) expected_in_box.push_back(x);
    EXPECT_EQ(in_box, expected_in_box) << "voxel " << v;
  }
  // The freed chunks and the emptied voxel are reused: the points go back in.
  EXPECT_EQ(map.insert(cloud_of(doomed_points), Eigen::Isometry3d::Identity()).inserted, doomed_points.size());
  EXPECT_EQ(map.size(), pts.size());
  EXPECT_EQ(map.voxel_count(), 4u);
}

TEST(LocalMap, KnnMatchesBruteForce) {
  LocalMap map(LocalMapParams{.voxel_size_m = 0.3, .min_point_distance_m = 0.0});
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<Eigen::Vector3d> pts(test::full_or_coarse(3000, 800));
  for (auto& p : pts) p = Eigen::Vector3d(u(rng), u(rng), u(rng));
  ASSERT_EQ(map.insert(cloud_of(pts), Eigen::Isometry3d::Identity()).inserted, pts.size());
  std::vector<Neighbour> out(80);
  for (int q = 0; q < test::full_or_coarse(300, 60); ++q) {
    const Eigen::Vector3d query(u(rng) * 1.5, u(rng) * 1.5, u(rng) * 1.5);
    // 40 in storage for 40: the heap; in storage for 80: collect and select.
    for (const auto& [k, storage] : {std::pair<std::size_t, std::size_t>{1, 1}, {8, 8}, {40, 40}, {40, 80}}) {
      const double radius = k == 40 ? 0.5 : 0.25;
      const std::size_t found = map.knn(query, radius, std::span<Neighbour>(out.data(), storage), k);
      std::vector<double> brute;
      for (const auto& p : pts)
        if ((p - query).squaredNorm() < radius * radius) brute.push_back((p - query).squaredNorm());
      std::sort(brute.begin(), brute.end());
      ASSERT_EQ(found, std::min(k, brute.size()));
      for (std::size_t i = 0; i < found; ++i) {
        EXPECT_DOUBLE_EQ(out[i].distance_sq, brute[i]);
        EXPECT_DOUBLE_EQ((map.position(out[i].index) - query).squaredNorm(), brute[i]);
      }
      // In any order: the same neighbours.
      ASSERT_EQ(map.knn(query, radius, std::span<Neighbour>(out.data(), storage), k, KnnOrder::kAny), found);
      std::vector<double> any_order;
      for (std::size_t i = 0; i < found; ++i) any_order.push_back((map.position(out[i].index) - query).squaredNorm());
      std::sort(any_order.begin(), any_order.end());
      for (std::size_t i = 0; i < found; ++i) EXPECT_DOUBLE_EQ(any_order[i], brute[i]);
    }
  }
}

TEST(LocalMap, InsertCandidatesAreThePointsWithNoMapPointWithinTheMinimumDistance) {
  LocalMap map(LocalMapParams{.min_point_distance_m = 0.05});
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Vector3d> mapped(500), scan(2000);
  for (auto& p : mapped) p = Eigen::Vector3d(u(rng), u(rng), u(rng));
  for (auto& p : scan) p = Eigen::Vector3d(u(rng), u(rng), u(rng));
  map.insert(cloud_of(mapped), Eigen::Isometry3d::Identity());
  const Eigen::Isometry3d T_wl = test::make_pose(Eigen::Vector3d(0.1, -0.2, 0.05), 0.1, 0.0, 0.3);
  std::vector<std::uint32_t> candidates;
  const std::size_t count = map.find_insert_candidates(cloud_of(scan).points, T_wl, candidates);
  ASSERT_EQ(count, candidates.size());
  std::vector<std::uint32_t> expected;
  std::vector<Eigen::Vector3d> in_map;
  map.for_each_point([&](const Eigen::Vector3d& p_w, const MapPoint&) { in_map.push_back(p_w); });
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Eigen::Vector3d p_w = T_wl * scan[i];
    const bool covered = std::any_of(in_map.begin(), in_map.end(), [&](const Eigen::Vector3d& q) { return (q - p_w).norm() < 0.05; });
    if (!covered) expected.push_back(static_cast<std::uint32_t>(i));
  }
  EXPECT_GT(expected.size(), 100u);
  EXPECT_LT(expected.size(), scan.size());
  EXPECT_EQ(candidates, expected);
}

TEST(LocalMap, NormalsOfTheRoomAreTheFaceNormals) {
  const test::Room room = test::make_room();
  const double spacing_m = test::full_or_coarse(0.1, 0.3);
  const PointCloud surfaces = test::sample_room_surfaces(room, spacing_m);
  LocalMapParams params;
  params.normals.min_other_line_neighbours = 0;  // samples, not a lidar scan
  LocalMap map(params);
  map.insert(surfaces, Eigen::Isometry3d::Identity());
  std::vector<Neighbour> neighbours;
  MapPoint own_fit;
  std::size_t checked = 0;
  for (const Eigen::Vector3d& q : surfaces.points) {
    // The ceiling (no obstacle reaches it), away from the walls: its points
    // fit its plane exactly.
    if (std::abs(q.z() - room.interior.hi.z()) > 1e-9) continue;
    const double dx = std::min(std::abs(q.x() - room.interior.lo.x()), std::abs(q.x() - room.interior.hi.x()));
    const double dy = std::min(std::abs(q.y() - room.interior.lo.y()), std::abs(q.y() - room.interior.hi.y()));
    if (dx < 3 * spacing_m || dy < 3 * spacing_m) continue;  // beyond the 20 neighbours' reach
    Neighbour self;
    ASSERT_EQ(map.knn(q, 1e-6, std::span<Neighbour>(&self, 1)), 1u);
    EXPECT_EQ(map.point(self.index).normal_state, kNormalUnfitted);  // fitted on first use only
    const MapPoint& p = map.fitted_point(self.index, neighbours, own_fit);
    EXPECT_EQ(&p, &map.point(self.index));  // kept in the map, not in own_fit
    ASSERT_TRUE(p.normal_valid);
    EXPECT_EQ(p.normal_state, kNormalFitted);
    EXPECT_NEAR(std::abs(p.normal_w.z()), 1.0, 1e-6);  // stored as float
    EXPECT_LT(p.normal_w.z(), 0.0f);  // toward the sensor at the origin, below the ceiling
    ++checked;
  }
  EXPECT_GT(checked, test::full_or_coarse(3000u, 300u));
}

}  // namespace
}  // namespace tumble
