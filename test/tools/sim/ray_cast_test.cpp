// The ray caster against ranges worked out by hand, and the scene's BVH
// against a brute-force nearest hit.
#include "tools/sim/motion.hpp"
#include "tools/sim/ray_cast.hpp"
#include "tools/sim/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace tumble::sim {
namespace {

Primitive make(Shape shape, const Eigen::Vector3d& centre, const Eigen::Vector3d& rpy_deg,
               const Eigen::Vector3d& half_size, double radius = 0, bool capped = true) {
  Primitive p;
  p.shape = shape;
  p.pose_w = pose_from_xyz_rpy_deg(centre, rpy_deg);
  p.half_size = half_size;
  p.radius_m = radius;
  p.capped = capped;
  return p;
}

Ray ray(const Eigen::Vector3d& o, const Eigen::Vector3d& d) { return {o, d.normalized()}; }

TEST(RayCast, TiltedPlaneRangeIsDistanceOverCosine) {
  // Plane through (5, 0, 0) tilted 30 deg about z from facing -x: its normal is (cos30, sin30, 0).
  const Primitive plane = make(Shape::Plane, {5, 0, 0}, {0, 90, 30}, Eigen::Vector3d::Zero());
  const Eigen::Vector3d n(std::cos(std::numbers::pi / 6), std::sin(std::numbers::pi / 6), 0);
  // Along +x from the origin: perpendicular distance 5 cos30, angle of incidence 30 deg.
  const auto hit = intersect(plane, ray(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()), 100);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t_m, 5.0, 1e-12);
  EXPECT_NEAR(std::abs(hit->normal_w.dot(n)), 1.0, 1e-12);
  EXPECT_LT(hit->normal_w.dot(Eigen::Vector3d::UnitX()), 0) << "normal must face the ray";
  // Along the normal: the perpendicular distance.
  const auto perp = intersect(plane, ray(Eigen::Vector3d::Zero(), n), 100);
  ASSERT_TRUE(perp);
  EXPECT_NEAR(perp->t_m, 5.0 * std::cos(std::numbers::pi / 6), 1e-12);
  // Parallel rays and rays pointing away miss; a short max range misses.
  EXPECT_FALSE(intersect(plane, ray(Eigen::Vector3d::Zero(), Eigen::Vector3d(-n.y(), n.x(), 0)), 100));
  EXPECT_FALSE(intersect(plane, ray(Eigen::Vector3d::Zero(), -n), 100));
  EXPECT_FALSE(intersect(plane, ray(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()), 4.9));
}

TEST(RayCast, RectangleHasEdges) {
  const Primitive rect = make(Shape::Rectangle, {0, 0, 2}, {0, 0, 0}, {1, 0.5, 0});
  const Eigen::Vector3d o(0, 0, 0);
  const auto inside = intersect(rect, ray(o, Eigen::Vector3d(0.99, 0, 2)), 100);
  ASSERT_TRUE(inside);
  EXPECT_NEAR(inside->t_m, std::hypot(0.99, 2.0), 1e-12);
  EXPECT_NEAR(inside->normal_w.z(), -1.0, 1e-12);
  EXPECT_FALSE(intersect(rect, ray(o, Eigen::Vector3d(1.01, 0, 2)), 100));
  EXPECT_FALSE(intersect(rect, ray(o, Eigen::Vector3d(0, 0.51, 2)), 100));
}

TEST(RayCast, BoxCornerFromOutside) {
  // Unit cube at the origin rotated 45 deg about z: its +x+y corner edge points along +x at x = sqrt(2)/2.
  const Primitive box = make(Shape::Box, {0, 0, 0}, {0, 0, 45}, {0.5, 0.5, 0.5});
  const double corner_x = std::sqrt(0.5);
  const auto hit = intersect(box, ray({10, 0, 0}, -Eigen::Vector3d::UnitX()), 100);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t_m, 10 - corner_x, 1e-12);
  // Slightly off the edge: a face at 45 deg, so the range grows by the offset.
  const auto off = intersect(box, ray({10, 0.1, 0}, -Eigen::Vector3d::UnitX()), 100);
  ASSERT_TRUE(off);
  EXPECT_NEAR(off->t_m, 10 - corner_x + 0.1, 1e-12);
  EXPECT_NEAR(off->normal_w.x(), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(off->normal_w.y(), std::sqrt(0.5), 1e-12);
  // Past the top face: miss.
  EXPECT_FALSE(intersect(box, ray({10, 0, 0.51}, -Eigen::Vector3d::UnitX()), 100));
}

TEST(RayCast, BoxCornerFromInsideLikeARoom) {
  const Primitive room = make(Shape::Box, {0, 0, 1.5}, {0, 0, 0}, {10, 5, 1.5});
  const Eigen::Vector3d o(1, 1, 1);
  // Towards the (10, 5, 3) corner: the walls are 9, 4 and 2 away along the axes; along (3, 1, 2) the ceiling comes first.
  const Eigen::Vector3d d = Eigen::Vector3d(3, 1, 2).normalized();
  const auto hit = intersect(room, ray(o, d), 100);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t_m, 2.0 / d.z(), 1e-12);
  EXPECT_NEAR(hit->normal_w.z(), -1.0, 1e-12) << "the ceiling, seen from below";
  // Exactly into the corner: all three walls at once, range = the distance to it.
  const Eigen::Vector3d corner(10, 5, 3);
  const auto c = intersect(room, ray(o, corner - o), 100);
  ASSERT_TRUE(c);
  EXPECT_NEAR(c->t_m, (corner - o).norm(), 1e-12);
  // Floor straight down.
  const auto floor = intersect(room, ray(o, -Eigen::Vector3d::UnitZ()), 100);
  ASSERT_TRUE(floor);
  EXPECT_NEAR(floor->t_m, 1.0, 1e-12);
  EXPECT_NEAR(floor->normal_w.z(), 1.0, 1e-12);
}

TEST(RayCast, CylinderHitAndMiss) {
  const Primitive pole = make(Shape::Cylinder, {5, 0, 1}, {0, 0, 0}, {0, 0, 1}, 0.5);
  const Eigen::Vector3d o(0, 0, 1);
  const auto hit = intersect(pole, ray(o, Eigen::Vector3d::UnitX()), 100);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t_m, 4.5, 1e-12);
  EXPECT_NEAR(hit->normal_w.x(), -1.0, 1e-12);
  // Offset by y = 0.3: chord at x = 5 - sqrt(0.25 - 0.09) = 4.6.
  const auto chord = intersect(pole, ray({0, 0.3, 1}, Eigen::Vector3d::UnitX()), 100);
  ASSERT_TRUE(chord);
  EXPECT_NEAR(chord->t_m, 4.6, 1e-12);
  EXPECT_NEAR(chord->normal_w.y(), 0.6, 1e-12);
  // Tangent-plus: misses; over the top: misses; the cap from above: hits.
  EXPECT_FALSE(intersect(pole, ray({0, 0.51, 1}, Eigen::Vector3d::UnitX()), 100));
  EXPECT_FALSE(intersect(pole, ray({0, 0, 2.1}, Eigen::Vector3d::UnitX()), 100));
  const auto cap = intersect(pole, ray({5.2, 0, 4}, -Eigen::Vector3d::UnitZ()), 100);
  ASSERT_TRUE(cap);
  EXPECT_NEAR(cap->t_m, 2.0, 1e-12);
  EXPECT_NEAR(cap->normal_w.z(), 1.0, 1e-12);
}

TEST(RayCast, TiltedAndOpenCylinder) {
  // A pipe along y (axis from rpy: roll -90 deg maps local z to +y), radius 1, open ends.
  const Primitive pipe = make(Shape::Cylinder, {0, 0, 0}, {-90, 0, 0}, {0, 0, 2}, 1.0, false);
  // From inside along the axis: no caps, nothing to hit.
  EXPECT_FALSE(intersect(pipe, ray({0, 0, 0}, Eigen::Vector3d::UnitY()), 100));
  // From inside sideways: the inner wall at 1, normal pointing back in.
  const auto wall = intersect(pipe, ray({0, 0, 0}, Eigen::Vector3d::UnitZ()), 100);
  ASSERT_TRUE(wall);
  EXPECT_NEAR(wall->t_m, 1.0, 1e-12);
  EXPECT_NEAR(wall->normal_w.z(), -1.0, 1e-12);
  // From outside at 45 deg in the x-z plane towards the axis.
  const Eigen::Vector3d o(3, 0.5, 3);
  const auto outer = intersect(pipe, ray(o, Eigen::Vector3d(-1, 0, -1)), 100);
  ASSERT_TRUE(outer);
  EXPECT_NEAR(outer->t_m, 3 * std::sqrt(2.0) - 1, 1e-12);
}

TEST(RayCast, SceneReturnsTheNearestOfTwoObjects) {
  Primitive near_box = make(Shape::Box, {4, 0, 0}, {0, 0, 0}, {0.5, 0.5, 0.5});
  near_box.reflectivity = 0.2;
  Primitive far_wall = make(Shape::Rectangle, {10, 0, 0}, {0, 90, 0}, {5, 5, 0});
  far_wall.reflectivity = 0.9;
  const Scene scene({far_wall, near_box});
  const auto hit = scene.cast(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 100);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 3.5, 1e-12);
  EXPECT_DOUBLE_EQ(hit->reflectivity, 0.2);
  // Beside the box: the wall.
  const auto beside = scene.cast({0, 1, 0}, Eigen::Vector3d::UnitX(), 100);
  ASSERT_TRUE(beside);
  EXPECT_NEAR(beside->range_m, 10.0, 1e-12);
  EXPECT_DOUBLE_EQ(beside->reflectivity, 0.9);
  // Max range below both: nothing.
  EXPECT_FALSE(scene.cast(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 3.0));
}

// Brute force over all primitives, to check the BVH traversal and its culling.
std::optional<double> brute_force(const Scene& scene, const Ray& r, double max_range) {
  std::optional<double> best;
  for (const Primitive& p : scene.primitives())
    if (auto h = intersect(p, r, best ? *best : max_range)) best = h->t_m;
  return best;
}

TEST(RayCast, BvhAgreesWithBruteForceOnARandomScene) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> pos(-10, 10), size(0.1, 2), angle(-180, 180);
  std::vector<Primitive> prims;
  prims.push_back(make(Shape::Plane, {0, 0, -5}, {0, 0, 0}, Eigen::Vector3d::Zero()));
  for (int i = 0; i < 120; ++i) {
    const Shape shape = i % 3 == 0 ? Shape::Box : (i % 3 == 1 ? Shape::Cylinder : Shape::Rectangle);
    prims.push_back(make(shape, {pos(rng), pos(rng), pos(rng)}, {angle(rng), angle(rng), angle(rng)},
                         {size(rng), size(rng), size(rng)}, size(rng), i % 2 == 0));
  }
  const Scene scene(prims);
  int hits = 0;
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d o(pos(rng), pos(rng), pos(rng));
    const Eigen::Vector3d d = Eigen::Vector3d(pos(rng), pos(rng), pos(rng)).normalized();
    const auto fast = scene.cast(o, d, 30);
    const auto slow = brute_force(scene, {o, d}, 30);
    ASSERT_EQ(fast.has_value(), slow.has_value()) << "ray " << i;
    if (!fast) continue;
    ++hits;
    EXPECT_DOUBLE_EQ(fast->range_m, *slow) << "ray " << i;
    EXPECT_NEAR(fast->normal_w.norm(), 1.0, 1e-12);
    EXPECT_LE(fast->normal_w.dot(d), 0.0);
  }
  EXPECT_GT(hits, 500 / 2) << "most rays should hit something, or the comparison proves little";
}

TEST(RayCast, AxisParallelRaysThroughTheBvh) {
  // Rays with zero direction components exercise the infinite 1/dir slabs.
  const Scene scene({make(Shape::Box, {0, 0, 0}, {0, 0, 0}, {1, 1, 1}), make(Shape::Box, {5, 0, 0}, {0, 0, 0}, {1, 1, 1}),
                     make(Shape::Box, {0, 5, 0}, {0, 0, 0}, {1, 1, 1})});
  const auto hit = scene.cast({-5, 0, 0}, Eigen::Vector3d::UnitX(), 100);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 4.0, 1e-12);
  // Along the top face plane of the first box (z = 1): boxes are closed sets, so its edge at y = -1 counts.
  const auto graze = scene.cast({0, -5, 1.0}, Eigen::Vector3d::UnitY(), 100);
  ASSERT_TRUE(graze);
  EXPECT_NEAR(graze->range_m, 4.0, 1e-12);
  EXPECT_FALSE(scene.cast({0, 0, 5}, Eigen::Vector3d::UnitX(), 100));
}

}  // namespace
}  // namespace tumble::sim
