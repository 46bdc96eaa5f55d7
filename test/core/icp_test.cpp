#include "core/icp.hpp"

#include <gtest/gtest.h>

#include <limits>

#include <random>

#include "core/voxel_grid.hpp"
#include "test/core/synthetic_room.hpp"

namespace tumble {
namespace {

constexpr double kDeg = M_PI / 180;

TEST(FrmsdTrim, KeepsExactlyTheInliersWhenTheirShareIsInsideTheRange) {
  // 62 % inliers with small residuals, 38 % outliers far away: FRMSD(r) falls
  // while r adds inliers and jumps at the first outlier, so r = 0.62.
  std::vector<double> d2;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> small(0.0, 0.01), large(0.5, 1.0);
  for (int i = 0; i < 620; ++i) d2.push_back(small(rng) * small(rng));
  for (int i = 0; i < 380; ++i) d2.push_back(large(rng));
  std::shuffle(d2.begin(), d2.end(), rng);
  std::vector<double> scratch;
  const FrmsdTrim trim = frmsd_trim(d2, 0.5, 0.7, 2.35, scratch);
  EXPECT_EQ(trim.kept, 620u);
  EXPECT_DOUBLE_EQ(trim.ratio, 0.62);
  EXPECT_LT(trim.threshold_sq, 1e-4);
  EXPECT_EQ(std::count_if(d2.begin(), d2.end(), [&](double v) { return v <= trim.threshold_sq; }), 620);
}

TEST(FrmsdTrim, ClampsToTheRange) {
  std::vector<double> d2;
  for (int i = 0; i < 100; ++i) d2.push_back(i < 90 ? 1e-4 : 100.0);  // 90 % inliers: above r_max
  std::vector<double> scratch;
  EXPECT_EQ(frmsd_trim(d2, 0.5, 0.7, 2.35, scratch).kept, 70u);
  // Residuals growing faster than any power of r: the least overlap wins.
  for (int i = 0; i < 100; ++i) d2[static_cast<std::size_t>(i)] = std::exp(0.5 * i);
  EXPECT_EQ(frmsd_trim(d2, 0.5, 0.7, 2.35, scratch).kept, 50u);
  EXPECT_EQ(frmsd_trim(std::span<const double>(), 0.5, 0.7, 2.35, scratch).kept, 0u);
}

TEST(FrmsdTrim, LambdaTradesOverlapForResidual) {
  // Residuals growing linearly with rank: a larger λ rewards a larger overlap.
  std::vector<double> d2;
  for (int i = 1; i <= 1000; ++i) d2.push_back(1e-6 * i * i);
  std::vector<double> scratch;
  const std::size_t low = frmsd_trim(d2, 0.05, 1.0, 0.5, scratch).kept;
  const std::size_t high = frmsd_trim(d2, 0.05, 1.0, 3.0, scratch).kept;
  EXPECT_LT(low, high);
  EXPECT_EQ(high, 1000u);  // sqrt(mean) ~ r, r^3 wins everywhere
}

// Surface samples are no lidar scan: every point is on "one scan line", so
// the scan-line test of the normals is off for them.
LocalMapParams sampled_map_params() {
  LocalMapParams params{.min_point_distance_m = 0.0};
  params.normals.min_other_line_neighbours = 0;
  return params;
}

struct RoomFixture {
  test::Room room = test::make_room();
  LocalMap map;
  PointCloud reading;  // frame L
  Eigen::Isometry3d truth = test::make_pose(Eigen::Vector3d(0.4, -0.3, 0.2), 2 * kDeg, -3 * kDeg, 25 * kDeg);

  // reading_from_map: the reading is the map's own samples seen from `truth`
  // (exact correspondences); otherwise a lidar scan of the room from `truth`.
  explicit RoomFixture(bool reading_from_map, double map_spacing_m = test::full_or_coarse(0.1, 0.3)) {
    const PointCloud surfaces = test::sample_room_surfaces(room, map_spacing_m);
    map = LocalMap(sampled_map_params());
    map.insert(surfaces, Eigen::Isometry3d::Identity());
    PointCloud raw;
    if (reading_from_map) {
      raw = surfaces;
      const Eigen::Isometry3d T_lw = truth.inverse();
      for (auto& p : raw.points) p = T_lw * p;
      for (auto& n : raw.normals) n = T_lw.linear() * n;
    } else {
      test::RingLidar lidar;
      lidar.columns = test::full_or_coarse(1800, 240);
      raw = test::to_cloud(test::scan_room(room, [&](double) { return truth; }, 0.0, lidar));
    }
    VoxelDownsampler(test::full_or_coarse(0.1, 0.3)).apply(raw, reading);
  }
};

Eigen::Isometry3d offset_guess(const Eigen::Isometry3d& truth) {
  // 0.5 m and 10 degrees away from the truth.
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 3).normalized();
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
  delta.linear() = Eigen::AngleAxisd(10 * kDeg, axis).toRotationMatrix();
  delta.translation() = Eigen::Vector3d(3, -2, 1).normalized() * 0.5;
  return delta * truth;
}

TEST(Icp, RecoversHalfMetreTenDegreeOffsetInARoom) {
  RoomFixture f(true);
  Icp icp;
  const IcpResult r = icp.align(f.reading, f.map, offset_guess(f.truth));
  EXPECT_TRUE(r.converged);
  EXPECT_LT((r.T_wl.translation() - f.truth.translation()).norm(), 1e-3);
  EXPECT_LT(test::rotation_error_rad(r.T_wl, f.truth), 0.01 * kDeg);
  EXPECT_FALSE(r.degeneracy.degenerate);
  EXPECT_GT(r.inlier_ratio, 0.49);
  EXPECT_LT(r.residual_rms_m, 1e-4);
  EXPECT_LT(r.iterations, 40);
}

TEST(Icp, RegistersALidarScanToASampledMap) {
  // Different samples on both sides: only the planes are shared.
  RoomFixture f(false);
  Icp icp;
  const IcpResult r = icp.align(f.reading, f.map, offset_guess(f.truth));
  EXPECT_TRUE(r.converged);
  EXPECT_LT((r.T_wl.translation() - f.truth.translation()).norm(), test::full_or_coarse(2e-3, 2e-2));
  EXPECT_LT(test::rotation_error_rad(r.T_wl, f.truth), test::full_or_coarse(0.05, 0.5) * kDeg);
  // Covariance: positive definite, translation std well under a centimetre.
  EXPECT_GT(r.covariance.ldlt().vectorD().minCoeff(), 0);
  EXPECT_LT(std::sqrt(r.covariance.diagonal().head<3>().maxCoeff()), 0.01);
}

TEST(Icp, ReusingNeighboursGivesTheSameMatchesAsSearchingEveryIteration) {
  RoomFixture f(false);
  IcpParams fresh_params;
  fresh_params.reuse_neighbours = false;
  Icp reuse, fresh(fresh_params);
  const IcpResult a = reuse.align(f.reading, f.map, offset_guess(f.truth));
  const IcpResult b = fresh.align(f.reading, f.map, offset_guess(f.truth));
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.matches_considered, b.matches_considered);
  EXPECT_EQ(a.matches_kept, b.matches_kept);
  // Same matches; the sums only differ in rounding.
  EXPECT_LT((a.T_wl.translation() - b.T_wl.translation()).norm(), 1e-9);
  EXPECT_LT(test::rotation_error_rad(a.T_wl, b.T_wl), 1e-9);
  EXPECT_EQ(b.neighbour_searches, f.reading.size() * static_cast<std::size_t>(b.iterations));
  EXPECT_LT(a.neighbour_searches, b.neighbour_searches);
}

TEST(Icp, ClockSplitsTheTimeBetweenMatchingAndSolving) {
  RoomFixture f(true);
  double fake_now = 0;
  Icp icp(IcpParams{}, [&] { return fake_now += 1.0; });  // every reading: one more second
  const IcpResult r = icp.align(f.reading, f.map, offset_guess(f.truth));
  ASSERT_TRUE(r.converged);
  EXPECT_DOUBLE_EQ(r.matching_s, r.iterations);
  EXPECT_DOUBLE_EQ(r.solve_s, r.iterations);
}

TEST(Icp, ZeroWeightOutliersAreIgnoredAndWeightedOnesPullTheSolution) {
  RoomFixture f(true);
  // A ghost copy of the reading shifted by 15 cm: a second, wrong surface.
  const std::size_t n = f.reading.size();
  PointCloud reading = f.reading;
  reading.resize(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    reading.copy_point(n + i, f.reading, i);
    reading.points[n + i] += Eigen::Vector3d(0.15, 0.1, 0.0);
  }
  // Keep every match so that only the weights decide.
  IcpParams params{.frmsd_r_min = 1.0, .frmsd_r_max = 1.0, .weighting = MatchWeighting::kPointWeight};
  Icp icp(params);
  for (std::size_t i = n; i < 2 * n; ++i) reading.weights[i] = 0.0;
  const IcpResult ignored = icp.align(reading, f.map, f.truth);
  EXPECT_LT((ignored.T_wl.translation() - f.truth.translation()).norm(), 1e-6);
  for (std::size_t i = n; i < 2 * n; ++i) reading.weights[i] = 1.0;
  const IcpResult pulled = icp.align(reading, f.map, f.truth);
  EXPECT_GT((pulled.T_wl.translation() - f.truth.translation()).norm(), 0.02);
  // Inverse-variance weighting: a huge sigma_s makes the ghost irrelevant.
  IcpParams variance_params = params;
  variance_params.weighting = MatchWeighting::kInverseVariance;
  Icp variance_icp(variance_params);
  for (std::size_t i = n; i < 2 * n; ++i) reading.sigma_s_m[i] = 1e4;
  const IcpResult down_weighted = variance_icp.align(reading, f.map, f.truth);
  EXPECT_LT((down_weighted.T_wl.translation() - f.truth.translation()).norm(), 1e-4);
}

// A stretch of corridor as the map and a ring scan from inside it that never
// sees the stretch's ends: nothing pins the translation along x.
struct CorridorFixture {
  LocalMap map{sampled_map_params()};
  PointCloud reading;
  Eigen::Isometry3d truth = test::make_pose(Eigen::Vector3d(0, 0.3, 0), 0, 0, 0.3);

  CorridorFixture() {
    const test::Room corridor = test::make_corridor();
    test::Room finite = corridor;
    finite.interior.lo.x() = -10;
    finite.interior.hi.x() = 10;
    finite.interior.hi.z() = 4;  // a ceiling above anything the reading sees
    map.insert(test::sample_room_surfaces(finite, test::full_or_coarse(0.1, 0.3)), Eigen::Isometry3d::Identity());
    test::RingLidar lidar;
    lidar.max_range_m = 8;
    lidar.columns = test::full_or_coarse(1800, 240);
    VoxelDownsampler(test::full_or_coarse(0.1, 0.3))
        .apply(test::to_cloud(test::scan_room(corridor, [&](double) { return truth; }, 0.0, lidar)), reading);
  }
};

TEST(Icp, FlagsACorridorDegenerateAlongItsAxis) {
  CorridorFixture f;
  Icp icp;
  Eigen::Isometry3d guess = f.truth;
  guess.translation() += Eigen::Vector3d(0.2, 0.05, 0.0);
  const IcpResult r = icp.align(f.reading, f.map, guess);
  ASSERT_TRUE(r.degeneracy.degenerate);
  EXPECT_GT(std::abs(r.degeneracy.direction(0)), 0.99);  // translation along x
  // Not exactly 0: PCA normals along the wall-floor edges lean a little along
  // x where k-NN ties on the sampling grid are broken one-sidedly.
  EXPECT_LT(r.degeneracy.min_eigenvalue, 1e-3);
  EXPECT_GT(r.degeneracy.condition_number, 1e3);
  // The constrained directions are still recovered.
  EXPECT_NEAR(r.T_wl.translation().y(), 0.3, 1e-3);
  EXPECT_LT(test::rotation_error_rad(r.T_wl, f.truth), test::full_or_coarse(0.02, 0.2) * kDeg);
  EXPECT_EQ(r.held_translation_w, Eigen::Vector3d::Zero());  // the paper's ICP holds nothing

  // The room is not degenerate.
  RoomFixture room(true);
  EXPECT_FALSE(icp.align(room.reading, room.map, room.truth).degeneracy.degenerate);
}

TEST(Icp, HoldsACorridorsAxisAtThePredictionAndStillSolvesTheRest) {
  CorridorFixture f;
  Icp icp(IcpParams{.hold_weak_translation_share = 0.002});
  // Off along the axis, across it, and in pitch and yaw.
  const Eigen::Isometry3d guess =
      test::make_pose(f.truth.translation() + Eigen::Vector3d(0.2, 0.05, 0.0), 0, 1 * kDeg, 0.3 + 1 * kDeg);
  const IcpResult r = icp.align(f.reading, f.map, guess);
  EXPECT_GT(std::abs(r.held_translation_w.x()), 0.99);
  // The prediction's along the held direction. Each iteration holds its own
  // weakest direction, which turns by a fraction of a degree between them.
  EXPECT_NEAR((r.T_wl.translation() - guess.translation()).dot(r.held_translation_w), 0.0, 1e-4);
  EXPECT_NEAR(r.T_wl.translation().y(), 0.3, 1e-3);
  EXPECT_LT(test::rotation_error_rad(r.T_wl, f.truth), test::full_or_coarse(0.02, 0.2) * kDeg);
  // The covariance still says the axis is unknown.
  EXPECT_LT(r.degeneracy.min_eigenvalue, 1e-3);
}

TEST(Icp, HoldsNothingWhereEveryDirectionIsPinned) {
  RoomFixture f(false);
  const IcpResult paper = Icp().align(f.reading, f.map, offset_guess(f.truth));
  const IcpResult ours = Icp(IcpParams{.hold_weak_translation_share = 0.002}).align(f.reading, f.map, offset_guess(f.truth));
  EXPECT_EQ(ours.held_translation_w, Eigen::Vector3d::Zero());
  EXPECT_TRUE(ours.T_wl.isApprox(paper.T_wl, 0.0));
  EXPECT_EQ(ours.iterations, paper.iterations);
}

TEST(Icp, APriorKeepsACorridorsAxisNearThePredictionAndLeavesThePinnedDirectionsToTheScan) {
  CorridorFixture f;
  Icp icp;  // no hold: the prior alone
  const Eigen::Isometry3d guess =
      test::make_pose(f.truth.translation() + Eigen::Vector3d(0.2, 0.05, 0.0), 0, 1 * kDeg, 0.3 + 1 * kDeg);
  // The noise-free corridor still pins its axis to millimetres (its edges'
  // normals lean along it), so the prior is a millimetre along x alone: it
  // decides x, the walls and floor decide y, z and the rotation.
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  information(0, 0) = 1.0 / (0.001 * 0.001);
  const IcpResult r = icp.align(f.reading, f.map, guess, information);
  EXPECT_NEAR(r.T_wl.translation().x(), guess.translation().x(), 0.002);
  EXPECT_NEAR(r.T_wl.translation().y(), 0.3, 1e-3);
  EXPECT_LT(test::rotation_error_rad(r.T_wl, f.truth), test::full_or_coarse(0.02, 0.2) * kDeg);
  // The covariance is the scan's own: the prior does not narrow it.
  EXPECT_GT(r.covariance(0, 0), 10 * 0.001 * 0.001);
  // Without it, x goes where the edges' normals say.
  const IcpResult free = icp.align(f.reading, f.map, guess);
  EXPECT_GT(std::abs(free.T_wl.translation().x() - guess.translation().x()), 0.02);
}

TEST(Icp, APriorThatIsNotFiniteIsNoPrior) {
  RoomFixture f(false);
  const Eigen::Isometry3d guess = offset_guess(f.truth);
  const IcpResult paper = Icp().align(f.reading, f.map, guess);
  const IcpResult broken = Icp().align(f.reading, f.map, guess,
                                       Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_TRUE(broken.T_wl.isApprox(paper.T_wl, 0.0));
}

TEST(Icp, APriorBarelyMovesAPoseTheScanPins) {
  RoomFixture f(false);
  const Eigen::Isometry3d guess = offset_guess(f.truth);
  const IcpResult paper = Icp().align(f.reading, f.map, guess);
  const IcpResult with_prior =
      Icp().align(f.reading, f.map, guess, Eigen::Matrix3d::Identity() / (0.02 * 0.02));
  EXPECT_LT((with_prior.T_wl.translation() - paper.T_wl.translation()).norm(), test::full_or_coarse(1e-3, 5e-3));
  EXPECT_LT((with_prior.T_wl.translation() - f.truth.translation()).norm(), test::full_or_coarse(0.005, 0.02));
}

TEST(Icp, MatchedRatioIsTheShareOfReadingPointsNearTheMap) {
  // The room's own samples match but those whose map normal is not valid
  // (edges, corners); the same many again, 5 m above the room (beyond
  // max_match_distance_m of any wall), match none: the share halves.
  RoomFixture f(true);
  Icp icp;
  const double in_room = icp.align(f.reading, f.map, f.truth).matched_ratio;
  EXPECT_GT(in_room, test::full_or_coarse(0.85, 0.7));  // coarse samples: more of them on edges
  const std::size_t n = f.reading.size();
  PointCloud doubled;
  doubled.resize(2 * n);
  const Eigen::Isometry3d T_lw = f.truth.inverse();
  for (std::size_t i = 0; i < n; ++i) {
    doubled.copy_point(i, f.reading, i);
    doubled.copy_point(n + i, f.reading, i);
    const Eigen::Vector3d p_w = f.truth * f.reading.points[i];
    doubled.points[n + i] = T_lw * Eigen::Vector3d(p_w.x(), p_w.y(), f.room.interior.hi.z() + 5.0);
  }
  const IcpResult r = icp.align(doubled, f.map, f.truth);
  EXPECT_DOUBLE_EQ(r.matched_ratio, in_room / 2);
  // FRMSD's share stays within its range whatever the overlap: it cannot tell.
  EXPECT_GE(r.inlier_ratio, 0.5);
}

TEST(Icp, NoMapMeansNoConvergence) {
  LocalMap empty;
  RoomFixture f(true, 0.4);
  Icp icp;
  const IcpResult r = icp.align(f.reading, empty, f.truth);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.matches_considered, 0u);
  EXPECT_TRUE(r.degeneracy.degenerate);
  EXPECT_TRUE(r.T_wl.isApprox(f.truth));
}

TEST(Icp, RejectsBadParameters) {
  EXPECT_THROW(Icp(IcpParams{.max_match_distance_m = 0}), std::invalid_argument);
  EXPECT_THROW(Icp(IcpParams{.match_k = 0}), std::invalid_argument);
  EXPECT_THROW(Icp(IcpParams{.frmsd_r_min = 0.8, .frmsd_r_max = 0.7}), std::invalid_argument);
  EXPECT_THROW(Icp(IcpParams{.hold_weak_translation_share = -0.1}), std::invalid_argument);
}

}  // namespace
}  // namespace tumble
