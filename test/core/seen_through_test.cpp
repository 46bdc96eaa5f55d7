#include "core/seen_through.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <thread>
#include <vector>

#include "test/core/cloud_of.hpp"

namespace tumble {
namespace {

using test::cloud_of;

const Eigen::Vector3d kSensor(0, 0, 0.5);

// A wall across x = 10 (y, z in [-2, 2] x [-1.5, 6]) and a person-sized block
// of points at x = 3, 5 cm apart: what the map held.
struct WallAndPerson {
  std::vector<Eigen::Vector3d> wall;
  std::vector<Eigen::Vector3d> person;
};

WallAndPerson wall_and_person() {
  WallAndPerson scene;
  for (double y = -2; y <= 2; y += 0.05)
    for (double z = -1.5; z <= 6; z += 0.05) scene.wall.emplace_back(10, y, z);
  for (double y = -0.25; y <= 0.25; y += 0.05)
    for (double z = 0.1; z <= 1.7; z += 0.05) scene.person.emplace_back(3, y, z);
  return scene;
}

LocalMap map_of(const std::vector<std::vector<Eigen::Vector3d>>& parts) {
  LocalMap map(LocalMapParams{.max_points_per_voxel = 4096, .min_point_distance_m = 0.0});
  for (const auto& part : parts) map.insert(cloud_of(part), Eigen::Isometry3d::Identity());
  return map;
}

// Beams from the sensor to each of `ends`, whose surface has `normal`.
std::vector<MapBeam> beams_to(const std::vector<Eigen::Vector3d>& ends, const Eigen::Vector3d& normal) {
  std::vector<MapBeam> beams;
  for (const auto& end : ends) beams.push_back(MapBeam{kSensor, end, normal});
  return beams;
}

// The scan's returns: the beams' ends.
std::vector<Eigen::Vector3d> ends_of(const std::vector<MapBeam>& beams) {
  std::vector<Eigen::Vector3d> ends;
  for (const auto& beam : beams) ends.push_back(beam.end_w);
  return ends;
}

std::size_t remove_with(const SeenThroughParams& params, LocalMap& map, const std::vector<MapBeam>& beams) {
  return SeenThroughRemover(params).remove(map, beams, ends_of(beams));
}

std::size_t count_near(const LocalMap& map, const std::vector<Eigen::Vector3d>& points) {
  std::size_t n = 0;
  for (const auto& p : points) {
    Neighbour nn;
    n += map.knn(p, 1e-6, std::span<Neighbour>(&nn, 1));
  }
  return n;
}

TEST(SeenThrough, APersonTheWallBehindIsNowSeenThroughLeavesTheMapAndTheWallStays) {
  const WallAndPerson scene = wall_and_person();
  LocalMap map = map_of({scene.wall, scene.person});
  const std::vector<MapBeam> beams = beams_to(scene.wall, Eigen::Vector3d(-1, 0, 0));
  const std::size_t removed = remove_with(SeenThroughParams{}, map, beams);
  // The beams are 5 cm apart on the wall, 1.5 cm at x = 3: every person point is within 3 cm of one.
  EXPECT_EQ(count_near(map, scene.person), 0u);
  EXPECT_EQ(removed, scene.person.size());
  EXPECT_EQ(count_near(map, scene.wall), scene.wall.size());
}

TEST(SeenThrough, PointsWithinTheMarginOfTheReturnOrBeyondTheRangeStay) {
  const WallAndPerson scene = wall_and_person();
  LocalMap map = map_of({scene.wall, scene.person});
  SeenThroughParams params;
  params.margin_m = 8.5;  // the returns are 7–8.1 m past the person along their beams
  EXPECT_EQ(remove_with(params, map, beams_to(scene.wall, Eigen::Vector3d(-1, 0, 0))), 0u);
  params = SeenThroughParams{};
  params.max_range_m = 2.9;  // the person is 3–3.5 m away along the beams
  EXPECT_EQ(remove_with(params, map, beams_to(scene.wall, Eigen::Vector3d(-1, 0, 0))), 0u);
  params.max_range_m = 30;
  params.enabled = false;
  EXPECT_EQ(remove_with(params, map, beams_to(scene.wall, Eigen::Vector3d(-1, 0, 0))), 0u);
  EXPECT_EQ(map.size(), scene.wall.size() + scene.person.size());
}

TEST(SeenThrough, AGrazingBeamKeepsTheFloorItReturnsFromButNotWhatStoodOnIt) {
  // A floor (z = 0) seen from 0.5 m up: beams 2–3 degrees down return from it
  // 10–14 m away, running within 3 cm of the floor for their last metre.
  std::vector<Eigen::Vector3d> floor, box;
  for (double x = 4; x <= 15; x += 0.05)
    for (double y = -0.5; y <= 0.5; y += 0.05) floor.emplace_back(x, y, 0);
  // A box 30 cm tall that stood on the floor at x = 8, where the beams pass 8-22 cm up.
  for (double y = -0.3; y <= 0.3; y += 0.05)
    for (double z = 0.12; z <= 0.3; z += 0.03) box.emplace_back(8, y, z);
  std::vector<MapBeam> beams;
  for (double down_deg = 2.0; down_deg <= 3.0; down_deg += 0.02) {
    for (double y = -0.4; y <= 0.4; y += 0.01) {
      const double x = 0.5 / std::tan(down_deg * M_PI / 180);
      beams.push_back(MapBeam{kSensor, Eigen::Vector3d(x, y * x / 10, 0), Eigen::Vector3d::UnitZ()});
    }
  }
  LocalMap map = map_of({floor, box});
  EXPECT_GT(remove_with(SeenThroughParams{}, map, beams), 0u);
  EXPECT_EQ(count_near(map, floor), floor.size());
  EXPECT_LT(count_near(map, box), box.size());
  // Without the returns' normals the far floor goes: seen this obliquely, its
  // own points have no normal either (NormalParams::min_cos_incidence).
  for (auto& beam : beams) beam.end_normal_w.setZero();
  LocalMap bare = map_of({floor});
  EXPECT_GT(remove_with(SeenThroughParams{}, bare, beams), 0u);
}

TEST(SeenThrough, ABeamAlongAWallKeepsTheWall) {
  // A wall at y = 0.8 (x in [2, 8]), mapped from the origin column by column;
  // beams from a sensor 2 cm from it run along it to a far wall at x = 20.
  std::vector<std::vector<Eigen::Vector3d>> columns;
  std::vector<Eigen::Vector3d> wall;
  for (double x = 2; x <= 8; x += 0.05) {
    columns.emplace_back();
    for (double z = 0; z <= 1; z += 0.05) columns.back().emplace_back(x, 0.8, z);
    wall.insert(wall.end(), columns.back().begin(), columns.back().end());
  }
  std::vector<MapBeam> beams;
  for (double z = 0.2; z <= 0.8; z += 0.01)
    beams.push_back(MapBeam{Eigen::Vector3d(0, 0.78, z), Eigen::Vector3d(20, 0.78, z), Eigen::Vector3d(-1, 0, 0)});
  LocalMap map = map_of(columns);
  EXPECT_EQ(remove_with(SeenThroughParams{}, map, beams), 0u);
  // Were it no surface to the test, the beams would take the wall they run along.
  SeenThroughParams no_grazing;
  no_grazing.grazing_cos = 0;
  EXPECT_GT(remove_with(no_grazing, map, beams), 0u);
  EXPECT_LT(count_near(map, wall), wall.size());
}

TEST(SeenThrough, AnEdgeTheScanStillSeesStays) {
  // A pillar's face at x = 5 (y in [0, 0.6]); beams pass 1-3 cm beyond its
  // edge at y = 0.6 to a wall at x = 10, and other beams of the scan hit the face.
  std::vector<Eigen::Vector3d> face, edge;
  for (double y = 0; y <= 0.6001; y += 0.05)
    for (double z = 0.5; z <= 1.5; z += 0.05) (y > 0.55 ? edge : face).emplace_back(5, y, z);
  std::vector<MapBeam> past_the_edge;
  for (double z = 0.5; z <= 1.5; z += 0.01) {
    const Eigen::Vector3d at_face(5, 0.62, z);
    past_the_edge.push_back(MapBeam{kSensor, kSensor + (at_face - kSensor) * 2.0, Eigen::Vector3d(-1, 0, 0)});
  }
  std::vector<Eigen::Vector3d> returns = ends_of(past_the_edge);
  for (const auto& p : face) returns.push_back(p);
  LocalMap seen = map_of({face, edge});
  EXPECT_EQ(SeenThroughRemover(SeenThroughParams{}).remove(seen, past_the_edge, returns), 0u);
  // A scan that no longer hits the face: the edge the beams passed goes.
  LocalMap gone = map_of({face, edge});
  EXPECT_EQ(remove_with(SeenThroughParams{}, gone, past_the_edge), edge.size());
  EXPECT_EQ(count_near(gone, face), face.size());
}

TEST(SeenThrough, APointNearTheBeamWhoseNearestPlaceOnItIsInTheNextCellGoes) {
  // Cells of 0.5 m. Heading (1, 1, 0)/√2, the beam enters cell (0, 0, 0) at
  // (0.49, 0, 0.25) and leaves it at (0.5, 0.01, 0.25). The point (0.43, 0,
  // 0.25), in that cell, is 4.2 cm from the beam, nearest to (0.46, -0.03,
  // 0.25) in the cell the beam came from, whose points it does not look at.
  const Eigen::Vector3d dir = Eigen::Vector3d(1, 1, 0).normalized();
  const Eigen::Vector3d on_line(0.49, 0, 0.25);
  const MapBeam beam{on_line - 2 * dir, on_line + 5 * dir, Eigen::Vector3d::Zero()};
  LocalMap map = map_of({{Eigen::Vector3d(0.43, 0, 0.25)}});
  EXPECT_EQ(remove_with(SeenThroughParams{}, map, {beam}), 1u);
}

TEST(SeenThrough, TheSamePointsGoOnAnyNumberOfThreads) {
  // Beams to the wall's left half only: part of the person goes.
  const WallAndPerson scene = wall_and_person();
  std::vector<Eigen::Vector3d> left_half;
  for (const auto& p : scene.wall)
    if (p.y() < 0) left_half.push_back(p);
  const std::vector<MapBeam> beams = beams_to(left_half, Eigen::Vector3d(-1, 0, 0));
  const std::vector<Eigen::Vector3d> returns = ends_of(beams);
  class TwoThreads : public ParallelRunner {
   public:
    std::size_t workers() const override { return 2; }
    void run(std::size_t n, RangeTask task) override {
      std::thread helper([&] { task(1, n / 2, n); });
      task(0, 0, n / 2);
      helper.join();
    }
  } two_threads;
  auto survivors = [&](ParallelRunner& runner) {
    LocalMap map = map_of({scene.wall, scene.person});
    SeenThroughRemover(SeenThroughParams{}, runner).remove(map, beams, returns);
    std::vector<std::array<double, 3>> kept;
    map.for_each_point([&](const Eigen::Vector3d& p, const MapPoint&) { kept.push_back({p.x(), p.y(), p.z()}); });
    std::sort(kept.begin(), kept.end());
    return kept;
  };
  const auto serial = survivors(serial_runner());
  EXPECT_LT(serial.size(), scene.wall.size() + scene.person.size());
  EXPECT_GT(serial.size(), scene.wall.size());
  EXPECT_EQ(survivors(two_threads), serial);
}

TEST(SeenThrough, ParametersOutOfRangeAreNamed) {
  EXPECT_THROW(SeenThroughRemover(SeenThroughParams{.beam_radius_m = 0}), std::invalid_argument);
  EXPECT_THROW(SeenThroughRemover(SeenThroughParams{.max_range_m = 0.1}), std::invalid_argument);
  EXPECT_THROW(SeenThroughRemover(SeenThroughParams{.grazing_cos = 1.5}), std::invalid_argument);
  EXPECT_THROW(SeenThroughRemover(SeenThroughParams{.support_radius_m = -0.1}), std::invalid_argument);
  try {
    SeenThroughRemover(SeenThroughParams{.margin_m = -1});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("margin_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace tumble
