#include "core/normals.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "core/point_grid.hpp"
#include "test/core/cloud_of.hpp"
#include "test/core/synthetic_room.hpp"

namespace tumble {
namespace {

// These clouds are no lidar scans (all points on "ring 0"): the scan-line
// test is off unless a test is about it.
NormalParams not_a_scan(int k, double max_radius_m = 1.0) {
  NormalParams p;
  p.k = k;
  p.max_radius_m = max_radius_m;
  p.min_other_line_neighbours = 0;
  return p;
}

using test::cloud_of;

TEST(NormalEstimator, PlaneNormalsFaceTheSensorWithZeroCurvature) {
  // A tilted plane far from the origin: the fit must not lose precision there.
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
  const Eigen::Vector3d origin(1000, -2000, 30);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) pts.push_back(origin + 0.05 * i * u + 0.05 * j * v);
  PointCloud cloud = cloud_of(pts);
  NormalEstimator estimator(not_a_scan(15));
  estimator.estimate(cloud, origin - 5 * n);  // sensor below the plane
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_TRUE(cloud.normal_valid[i]);
    EXPECT_NEAR(cloud.normals[i].dot(-n), 1.0, 1e-9);
    EXPECT_NEAR(cloud.curvatures[i], 0.0, 1e-9);
  }
}

TEST(NormalEstimator, SphereNormalsAreRadialWithSmallCurvature) {
  const double radius = 2.0;
  std::vector<Eigen::Vector3d> pts;  // Fibonacci sphere: near-uniform spacing (11 / 22 cm)
  const int n = test::full_or_coarse(4000, 1000);
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - 2 * (i + 0.5) / n, r = std::sqrt(1 - z * z), a = golden * i;
    pts.emplace_back(radius * r * std::cos(a), radius * r * std::sin(a), radius * z);
  }
  PointCloud cloud = cloud_of(pts);
  NormalEstimator estimator(not_a_scan(15));
  estimator.estimate(cloud, Eigen::Vector3d::Zero());  // sensor at the centre: normals point inward
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_TRUE(cloud.normal_valid[i]);
    EXPECT_GT(cloud.normals[i].dot(-pts[i].normalized()), std::cos(2.0 * M_PI / 180)) << i;
    EXPECT_GT(cloud.curvatures[i], 0.0);
    EXPECT_LT(cloud.curvatures[i], 0.01);
  }
}

TEST(NormalEstimator, CurvatureIsHighOnAnEdge) {
  std::vector<Eigen::Vector3d> pts;  // two perpendicular half-planes meeting at x = 0
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j) pts.emplace_back(i <= 0 ? 0.05 * i : 0.0, 0.05 * j, i <= 0 ? 0.0 : 0.05 * i);
  PointCloud cloud = cloud_of(pts);
  NormalEstimator estimator(not_a_scan(20));
  estimator.estimate(cloud, Eigen::Vector3d(-1, 0, 1));
  const std::size_t edge = 10 * 21 + 10;  // i = 0, j = 0
  const std::size_t flat = 0;             // i = -10, j = -10
  EXPECT_GT(cloud.curvatures[edge], 0.02);
  EXPECT_NEAR(cloud.curvatures[flat], 0.0, 1e-12);
}

TEST(NormalEstimator, DegenerateNeighbourhoodsAreFlaggedAndFacetheSensor) {
  // A line (one lidar ring on a wall), an isolated pair and a repeated point.
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 20; ++i) pts.emplace_back(0.05 * i, 0, 0);
  pts.emplace_back(50, 50, 50);
  pts.emplace_back(50.01, 50, 50);
  for (int i = 0; i < 5; ++i) pts.emplace_back(-50, 0, 0);
  PointCloud cloud = cloud_of(pts);
  NormalEstimator estimator(not_a_scan(10, 0.5));
  const Eigen::Vector3d sensor(0, 0, 10);
  estimator.estimate(cloud, sensor);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_FALSE(cloud.normal_valid[i]) << i;
    EXPECT_TRUE(cloud.normals[i].allFinite());
    EXPECT_NEAR(cloud.normals[i].norm(), 1.0, 1e-12);
    EXPECT_NEAR(cloud.normals[i].dot((sensor - pts[i]).normalized()), 1.0, 1e-12);
  }
}

TEST(NormalEstimator, OneRingAcrossACornerIsNoSurface) {
  // One ring of a lidar at the origin crossing the corner of two walls
  // (x = 3 and y = 3) at 20 deg elevation: a V of points that is exactly planar
  // (the cone's secant plane) but not a surface. A second ring makes it an edge.
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::uint8_t> rings;
  for (const double elevation_deg : {20.0, 22.0}) {
    for (double az = 30; az <= 60; az += 0.5) {
      const double a = az * M_PI / 180, e = elevation_deg * M_PI / 180;
      const Eigen::Vector3d dir(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      const double range = std::min(3.0 / dir.x(), 3.0 / dir.y());
      pts.push_back(dir * range);
      rings.push_back(elevation_deg < 21 ? 0 : 1);
    }
  }
  const std::size_t corner = 30;  // azimuth 45 deg on the first ring
  PointCloud one_ring = cloud_of(std::vector<Eigen::Vector3d>(pts.begin(), pts.begin() + 61));
  NormalParams params;
  params.k = 15;
  params.line_retry_k = 0;
  NormalEstimator estimator(params);
  estimator.estimate(one_ring, Eigen::Vector3d::Zero());
  EXPECT_FALSE(one_ring.normal_valid[corner]);
  // Without the rule (and the grazing test, which catches some of these) the
  // V passes as a plane whose normal is neither wall's.
  params.min_other_line_neighbours = 0;
  params.min_cos_incidence = 0;
  NormalEstimator fooled(params);
  fooled.estimate(one_ring, Eigen::Vector3d::Zero());
  ASSERT_TRUE(one_ring.normal_valid[corner]);
  EXPECT_LT(std::abs(one_ring.normals[corner].x()), 0.95);
  EXPECT_LT(std::abs(one_ring.normals[corner].y()), 0.95);
  // Two rings: a real edge, which the curvature shows (the ICP's normal
  // agreement test, not the fit, keeps such blended normals out of matches).
  PointCloud two_rings = cloud_of(pts);
  two_rings.rings = rings;
  NormalEstimator strict{NormalParams{.k = 15}};
  strict.estimate(two_rings, Eigen::Vector3d::Zero());
  EXPECT_GT(two_rings.curvatures[corner], 0.01);
  const std::size_t on_wall = 2;  // azimuth 31 deg: well inside the x = 3 wall
  EXPECT_TRUE(two_rings.normal_valid[on_wall]);
  EXPECT_NEAR(std::abs(two_rings.normals[on_wall].x()), 1.0, 1e-6);
}

TEST(NormalEstimator, NormalsOfListedPointsEqualThoseOfTheWholeCloud) {
  const test::Room room = test::make_room();
  PointCloud all = test::to_cloud(test::scan_room(room, [](double) { return Eigen::Isometry3d::Identity(); }, 0.0,
                                                  test::RingLidar{.columns = test::full_or_coarse(900, 200)}));
  PointCloud some = all;
  NormalEstimator estimator;
  estimator.estimate(all, Eigen::Vector3d::Zero());
  std::vector<std::uint32_t> listed;
  for (std::uint32_t i = 0; i < some.size(); i += 7) listed.push_back(i);
  estimator.index(some);
  estimator.estimate(some, Eigen::Vector3d::Zero(), listed);
  for (const std::uint32_t i : listed) {
    EXPECT_EQ(some.normals[i], all.normals[i]) << i;
    EXPECT_EQ(some.curvatures[i], all.curvatures[i]) << i;
    EXPECT_EQ(some.normal_valid[i], all.normal_valid[i]) << i;
  }
}

TEST(PointGrid, KnnMatchesBruteForce) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-3, 3);
  std::vector<Eigen::Vector3d> pts(test::full_or_coarse(3000, 800));
  for (auto& p : pts) p = Eigen::Vector3d(u(rng), u(rng), u(rng) * 0.2);
  PointGrid grid;
  grid.build(pts, 0.3);
  for (int q = 0; q < test::full_or_coarse(300, 60); ++q) {
    // k = 12: insertion; k = 80 in storage for 80: the heap; in storage for 160: collect and select.
    const std::size_t k = q % 3 == 0 ? 12 : 80;
    std::vector<Neighbour> out(q % 3 == 2 ? 160 : k);
    const Eigen::Vector3d query(u(rng), u(rng), u(rng));
    const double radius = q % 2 ? 0.7 : 10.0;
    const std::size_t found = grid.knn(query, radius, out, k);
    std::vector<std::pair<double, std::uint32_t>> brute;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const double d2 = (pts[i] - query).squaredNorm();
      if (d2 < radius * radius) brute.emplace_back(d2, static_cast<std::uint32_t>(i));
    }
    std::sort(brute.begin(), brute.end());
    ASSERT_EQ(found, std::min<std::size_t>(brute.size(), k));
    for (std::size_t k = 0; k < found; ++k) {
      EXPECT_DOUBLE_EQ(out[k].distance_sq, brute[k].first);
      EXPECT_EQ(out[k].index, brute[k].second);
    }
    // In any order: the same neighbours.
    ASSERT_EQ(grid.knn(query, radius, out, k, KnnOrder::kAny), found);
    std::sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(found),
              [](const Neighbour& a, const Neighbour& b) { return a.distance_sq < b.distance_sq; });
    for (std::size_t k = 0; k < found; ++k) EXPECT_EQ(out[k].index, brute[k].second);
  }
}

}  // namespace
}  // namespace tumble
