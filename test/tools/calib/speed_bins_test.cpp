// Bin statistics: quartiles as R/NumPy compute them, bins centred on the
// nominal speeds with edges halfway between.
#include "tools/calib/speed_bins.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace tumble::calib {
namespace {

TEST(Quartiles, InterpolateBetweenOrderStatistics) {
  // NumPy: np.percentile([7, 1, 3, 5], [25, 50, 75]) = [2.5, 4, 5.5].
  Quartiles q = quartiles({7, 1, 3, 5});
  EXPECT_DOUBLE_EQ(q.q1, 2.5);
  EXPECT_DOUBLE_EQ(q.median, 4.0);
  EXPECT_DOUBLE_EQ(q.q3, 5.5);
  q = quartiles({1, 2, 3, 4, 5});
  EXPECT_DOUBLE_EQ(q.q1, 2.0);
  EXPECT_DOUBLE_EQ(q.median, 3.0);
  EXPECT_DOUBLE_EQ(q.q3, 4.0);
  q = quartiles({-0.5});
  EXPECT_DOUBLE_EQ(q.q1, -0.5);
  EXPECT_DOUBLE_EQ(q.q3, -0.5);
  EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2.0);
  EXPECT_THROW(quartiles({}), std::invalid_argument);
}

TEST(SpeedBins, CentresAreZeroAndTheDistinctNominalSpeeds) {
  const std::vector<double> nominal{0.25, -0.25, 1.0, -3.5, 3.5, 1.0};
  const std::vector<double> centres = bin_centres(nominal);
  EXPECT_EQ(centres, (std::vector<double>{0.0, 0.25, 1.0, 3.5}));
  EXPECT_EQ(bin_centres({}), std::vector<double>{0.0});
}

TEST(SpeedBins, AScanGoesToTheNearestCentreByItsTrueSpeed) {
  const std::vector<double> centres{0.0, 0.25, 1.0, 3.5};
  EXPECT_EQ(bin_of(centres, 0.0), 0u);
  EXPECT_EQ(bin_of(centres, 0.12), 0u);
  EXPECT_EQ(bin_of(centres, 0.13), 1u);
  EXPECT_EQ(bin_of(centres, -0.9), 2u);  // the sign of travel does not matter
  EXPECT_EQ(bin_of(centres, 2.2), 2u);
  EXPECT_EQ(bin_of(centres, 2.3), 3u);
  EXPECT_EQ(bin_of(centres, 9.0), 3u);
  EXPECT_EQ(bin_of(centres, 0.625), 1u);  // a tie goes to the lower bin
  EXPECT_THROW(bin_of({}, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace tumble::calib
