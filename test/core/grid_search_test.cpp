#include "core/grid_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace tumble {
namespace {

TEST(GridSearch, CellsAreTheFloorOfTheCoordinatesOnBothSidesOfZeroAndOnTheBoundaries) {
  const double next_below_zero = std::nextafter(0.0, -1.0);
  const double next_below_two = std::nextafter(2.0, 0.0);
  for (const double x : {0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 2.0, -2.0, next_below_zero, next_below_two, -next_below_two,
                         1e6 + 0.25, -1e6 - 0.25, 2147483647.5, -2147483647.5, -2147483648.0}) {
    EXPECT_EQ(floor_to_int(x), static_cast<std::int32_t>(std::floor(x))) << x;
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-3000, 3000);
  for (int i = 0; i < 10000; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const CellKey key = cell_of(p, 1.0 / 0.05);
    EXPECT_EQ(key.x, static_cast<std::int32_t>(std::floor(p.x() * 20.0)));
    EXPECT_EQ(key.y, static_cast<std::int32_t>(std::floor(p.y() * 20.0)));
    EXPECT_EQ(key.z, static_cast<std::int32_t>(std::floor(p.z() * 20.0)));
  }
}

}  // namespace
}  // namespace tumble
