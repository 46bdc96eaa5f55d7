// Mixed pixels (LidarConfig::mixed_pixels): a beam whose footprint straddles
// the vertical edge of a board in front of a wall reads between the two when
// they are close, one or the other when they are far apart, and a footprint
// on one surface reads as the centre ray does.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "test/tools/sim/sensor_test_support.hpp"
#include "tools/sim/lidar_model.hpp"

namespace tumble::sim {
namespace {

using test::SpinMotion;

// A board whose face x = 5 m covers y < 0 (its edge at azimuth 0, the
// packet's middle) and, when wall_x_m > 0, a wall x = wall_x_m behind it.
Scene board_before_wall(double wall_x_m, bool with_board = true) {
  std::vector<Primitive> objects;
  if (with_board) {
    Primitive board;
    board.shape = Shape::Box;
    board.half_size = Eigen::Vector3d(0.05, 2.5, 10.0);
    board.pose_w.translation() = Eigen::Vector3d(5.05, -2.5, 0.0);
    objects.push_back(board);
  }
  Primitive wall;
  wall.shape = Shape::Plane;
  wall.pose_w = Eigen::Translation3d(wall_x_m, 0, 0) * Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY());
  objects.push_back(wall);
  return Scene(std::move(objects));
}

// x of every return of one packet spanning azimuth 357.6..2.4 deg from a unit at rest.
std::vector<double> returned_x(const Scene& scene, bool mixed_pixels) {
  LidarConfig config;
  config.range_noise_m = 0.0;
  config.dropout_probability = 0.0;
  config.mixed_pixels = mixed_pixels;
  const LidarUnit unit = make_lidar_unit(1, config);
  const SpinMotion still({0, 0, 0}, 0.0, 1.0);
  LidarModel model(config, unit, scene, still, 1, 357.6);
  rs16::MsopPacketData packet;
  model.fill_packet(0, packet);
  const auto blocks = block_azimuths_centideg(357.6, 3600.0, 0);
  std::vector<double> xs;
  for (int b = 0; b < 12; ++b) {
    for (int c = 0; c < 32; ++c) {
      const double range_m = packet.blocks[static_cast<std::size_t>(b)].channels[static_cast<std::size_t>(c)].distance_m;
      EXPECT_GT(range_m, 0.0);
      const Beam beam = rs16_beam(channel_azimuth_deg(blocks, b, c, 600),
                                  unit.vertical_angles_deg[static_cast<std::size_t>(c % 16)]);
      xs.push_back(beam.origin_l.x() + range_m * beam.direction_l.x());
    }
  }
  return xs;
}

int count_between(const std::vector<double>& xs, double lo, double hi) {
  int n = 0;
  for (const double x : xs) n += x > lo && x < hi;
  return n;
}

TEST(LidarMixedPixels, AFootprintOnABoardEdgeReadsBetweenTheBoardAndTheWallBehind) {
  const Scene scene = board_before_wall(5.5);
  const auto off = returned_x(scene, false), on = returned_x(scene, true);
  EXPECT_EQ(count_between(off, 5.0 + 1e-6, 5.5 - 1e-6), 0);
  // Each laser crosses the edge once per packet; its 3 mrad footprint
  // catches it in most of the 16.
  EXPECT_GE(count_between(on, 5.02, 5.48), 4);
  EXPECT_LE(count_between(on, 5.0 + 1e-6, 5.5 - 1e-6), 16);
  for (const double x : on) {
    EXPECT_GE(x, 5.0 - 1e-6);
    EXPECT_LE(x, 5.5 + 1e-6);
  }
}

TEST(LidarMixedPixels, SurfacesFarApartGiveTheStrongerEchoNotOneBetween) {
  // Within one echo the footprint's rays differ by millimetres (their slant).
  const auto on = returned_x(board_before_wall(9.0), true);
  EXPECT_EQ(count_between(on, 5.005, 8.995), 0);
  EXPECT_GT(count_between(on, 4.995, 5.005), 100);
  EXPECT_GT(count_between(on, 8.995, 9.005), 100);
}

TEST(LidarMixedPixels, AFootprintOnOneSurfaceReadsAsTheCentreRay) {
  const Scene wall = board_before_wall(7.0, false);
  EXPECT_EQ(returned_x(wall, true), returned_x(wall, false));
}

}  // namespace
}  // namespace tumble::sim
