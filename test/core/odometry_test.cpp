#include "core/odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test/core/room_drive.hpp"
#include "test/core/synthetic_room.hpp"

namespace tumble {
namespace {

using test::YawAndDrive;

OdometryParams test_params(bool deskew) {
  OdometryParams p;
  p.deskew = deskew;
  p.fuser.static_duration_s = 0.3;
  // While the drive accelerates (3 m/s², inside the accelerometer gate),
  // Madgwick turns the attitude toward the apparent gravity by 2β·dt per
  // sample (0.2 rad/s at the default β = 0.1), and de-skewing takes that
  // false rotation for motion: at β = 0.1 these runs err by 13 mm / 0.6 deg.
  // That is the fuser's (reported); this test is about the registration
  // pipeline, so β is small.
  p.fuser.madgwick.beta = 0.01;
  p.voxel_size_m = test::full_or_coarse(0.05, 0.15);
  if (test::kCoarseTests) {  // sparse clouds: bigger search cells keep the searches short
    p.reading_normals.grid_cell_m = 0.5;
    p.map.voxel_size_m = 0.5;
  }
  return p;
}

// Tracking runs: 2.5 s at full resolution, 0.9 s in coarse builds.
constexpr double kRunDuration_s = test::full_or_coarse(2.5, 0.9);

struct RunSummary {
  std::vector<ScanResult> results;
  double max_translation_error_m = 0;
  double max_rotation_error_rad = 0;
  double final_translation_error_m = 0;
  std::size_t fused_poses = 0;
};

// Runs the drive through the room and compares each registered pose with the truth.
RunSummary run(const YawAndDrive& motion, const OdometryParams& params, double duration_s, const test::RingLidar& lidar,
               const test::Room& room = test::make_room()) {
  Odometry odometry(params);
  RunSummary summary;
  odometry.set_scan_callback([&](const ScanResult& r) { summary.results.push_back(r); });
  odometry.set_pose_callback([&](const TrajectorySample&) { ++summary.fused_poses; });
  test::feed_room_drive(odometry, motion, duration_s, lidar, room);
  for (const ScanResult& r : summary.results) {
    const Eigen::Isometry3d truth = motion.pose(r.t_scan_start_s);
    const double dt = (r.T_wl.translation() - truth.translation()).norm();
    summary.max_translation_error_m = std::max(summary.max_translation_error_m, dt);
    summary.max_rotation_error_rad = std::max(summary.max_rotation_error_rad, test::rotation_error_rad(r.T_wl, truth));
    summary.final_translation_error_m = dt;
  }
  return summary;
}

test::RingLidar small_lidar() {
  test::RingLidar lidar;
  lidar.columns = test::full_or_coarse(900, 120);  // 0.4 / 3 deg: fewer points than an RS-16
  return lidar;
}

TEST(Odometry, TracksASmoothDriveAndTurnInARoom) {
  const YawAndDrive motion;
  // The default registers a coarser subset; 0 registers every point (the paper).
  for (const double registration_voxel_m : {OdometryParams{}.registration_voxel_size_m, 0.0}) {
    SCOPED_TRACE(registration_voxel_m);
    OdometryParams params = test_params(true);
    params.registration_voxel_size_m = registration_voxel_m;
    const RunSummary s = run(motion, params, kRunDuration_s, small_lidar());
    // Scans from the fuser's initialisation (0.3 s) on; the last may still wait.
    const auto expected_scans = static_cast<std::size_t>((kRunDuration_s - 0.3) / 0.1) - 1;
    ASSERT_GE(s.results.size(), expected_scans);
    EXPECT_GT(s.fused_poses, static_cast<std::size_t>((kRunDuration_s - 0.3) / 0.01) - 2);
    std::size_t registered = 0;
    for (const ScanResult& r : s.results) {
      EXPECT_TRUE(r.registered);
      if (registration_voxel_m > params.voxel_size_m) {
        EXPECT_LT(r.points_registered, r.points_downsampled);
      } else {
        EXPECT_EQ(r.points_registered, r.points_downsampled);
      }
      if (r.map_initialised) continue;
      ++registered;
      EXPECT_TRUE(r.converged) << r.scan_index;
      EXPECT_FALSE(r.degeneracy.degenerate) << r.scan_index;
      EXPECT_GT(r.inlier_ratio, 0.45);
    }
    EXPECT_EQ(registered + 1, s.results.size());
    // Moved metres and turned radians: the registered poses stay within millimetres.
    EXPECT_GT(motion.pose(kRunDuration_s - 0.1).translation().norm(), test::full_or_coarse(1.5, 0.05));
    // Coarse builds see 5x fewer points per scan: centimetres, not millimetres.
    EXPECT_LT(s.max_translation_error_m, test::kCoarseTests ? 0.03 : 5e-3);
    EXPECT_LT(s.max_rotation_error_rad, (test::kCoarseTests ? 0.5 : 0.15) * M_PI / 180);
    // The fused velocity follows the motion.
    const ScanResult& last = s.results.back();
    EXPECT_LT((last.v_w - motion.velocity_w * motion.speed_fraction(last.t_scan_start_s)).norm(), 0.05);
  }
}

TEST(Odometry, TracksTheDriveWithScanLineNormalsToo) {
  OdometryParams params = test_params(true);
  params.reading_normal_source = ReadingNormalSource::kScanLines;
  const RunSummary s = run(YawAndDrive{}, params, kRunDuration_s, small_lidar());
  ASSERT_GE(s.results.size(), static_cast<std::size_t>((kRunDuration_s - 0.3) / 0.1) - 1);
  for (const ScanResult& r : s.results) EXPECT_TRUE(r.registered) << r.scan_index;
  EXPECT_LT(s.max_translation_error_m, test::kCoarseTests ? 0.03 : 5e-3);
  EXPECT_LT(s.max_rotation_error_rad, (test::kCoarseTests ? 0.5 : 0.15) * M_PI / 180);
}

TEST(Odometry, ACorridorsAxisIsPublishedAsUnobservedAndTheRoomsDirectionsAreNot) {
  // Straight down the corridor: nothing but the IMU follows x. Once the window
  // of recent scans is full of weak ones, each scan says so and its published
  // covariance is sigma_m wide along x; in the room no scan is weak.
  OdometryParams params = test_params(true);
  params.unobserved.window_scans = 5;
  // This noise-free corridor's weakest eigenvalue is 0.0012-0.0020 (its
  // edges' normals lean along x), the room's at least 0.0046.
  params.unobserved.weak_min_eigenvalue = 0.003;
  const double duration_s = test::full_or_coarse(1.5, 1.2);
  YawAndDrive down_the_axis;
  down_the_axis.velocity_w = Eigen::Vector3d(1.0, 0.0, 0.0);
  down_the_axis.yaw_rate_rad_s = 0.0;
  const RunSummary corridor = run(down_the_axis, params, duration_s, small_lidar(), test::make_corridor());
  std::size_t on_map = 0, unobserved = 0;
  for (const ScanResult& r : corridor.results) {
    if (r.map_initialised || !r.registered) continue;
    ++on_map;
    EXPECT_LT(r.degeneracy.min_eigenvalue, params.unobserved.weak_min_eigenvalue) << r.scan_index;
    EXPECT_EQ(r.direction_unobserved, on_map >= params.unobserved.window_scans) << r.scan_index;
    if (!r.direction_unobserved) {
      EXPECT_LT(r.expected_error_m, 0.05) << r.scan_index;  // what s²·H⁻¹ claims from the normals' noise
      continue;
    }
    ++unobserved;
    EXPECT_GT(r.expected_error_m, 0.95 * params.unobserved.sigma_m) << r.scan_index;
    EXPECT_GT(r.covariance_published(0, 0), 0.9 * params.unobserved.sigma_m * params.unobserved.sigma_m) << r.scan_index;
    EXPECT_LT(r.covariance_published(1, 1), 0.01) << r.scan_index;  // across the corridor: still pinned
  }
  EXPECT_GE(unobserved, 3u);

  const RunSummary room = run(YawAndDrive{}, params, duration_s, small_lidar());
  ASSERT_GE(room.results.size(), params.unobserved.window_scans + 2);
  for (const ScanResult& r : room.results) {
    EXPECT_FALSE(r.direction_unobserved) << r.scan_index;
    if (!r.map_initialised) {
      EXPECT_GT(r.degeneracy.min_eigenvalue, params.unobserved.weak_min_eigenvalue) << r.scan_index;
    }
  }
}

TEST(Odometry, AWeakScanHoldsTheCorridorsAxisBeforeAndAfterTheDirectionIsDeclaredUnobserved) {
  // The corridor above, with the hold on at the weak-scan threshold (as
  // tumbled's config sets it): every weak scan holds x at the prediction,
  // those after the window declared x unobserved too (free there, ICP
  // followed the rings' pattern and bench2's corridor walks stood still).
  OdometryParams params = test_params(true);
  params.unobserved.window_scans = 5;
  params.unobserved.weak_min_eigenvalue = 0.003;
  params.icp.hold_weak_translation_share = params.unobserved.weak_min_eigenvalue;
  YawAndDrive down_the_axis;
  down_the_axis.velocity_w = Eigen::Vector3d(1.0, 0.0, 0.0);
  down_the_axis.yaw_rate_rad_s = 0.0;
  const RunSummary corridor =
      run(down_the_axis, params, test::full_or_coarse(1.5, 1.2), small_lidar(), test::make_corridor());
  std::size_t held_before = 0, held_after = 0;
  for (const ScanResult& r : corridor.results) {
    if (r.map_initialised || !r.registered) continue;
    // The attitude stays pinned: the fuser lets such a scan level it.
    EXPECT_LT(r.expected_rotation_error_icp_rad, ImuFuserParams{}.levelling_max_rotation_error_rad) << r.scan_index;
    if (r.degeneracy.min_eigenvalue >= params.icp.hold_weak_translation_share) continue;  // not weak: nothing held
    EXPECT_GT(std::abs(r.held_translation_w.x()), 0.99) << r.scan_index;
    ++(r.direction_unobserved ? held_after : held_before);
  }
  EXPECT_GE(held_before, params.unobserved.window_scans - 1);
  EXPECT_GE(held_after, 3u);

  const RunSummary room = run(YawAndDrive{}, params, test::full_or_coarse(1.5, 1.2), small_lidar());
  for (const ScanResult& r : room.results) EXPECT_EQ(r.held_translation_w, Eigen::Vector3d::Zero()) << r.scan_index;
}

TEST(Odometry, ThePredictionIsThePriorUntilTheDirectionIsDeclaredUnobservedAndBoundsTheWeakAxis) {
  // The corridor again, with the prediction as ICP's prior (as tumbled's
  // config sets it): every scan on the map has it until the window declares
  // x unobserved; the published covariance along x is the prediction's,
  // growing scan by scan, and from the scan that declares it on the scan's
  // own, widened.
  OdometryParams params = test_params(true);
  params.unobserved.window_scans = 5;
  params.unobserved.weak_min_eigenvalue = 0.003;
  params.position.prediction_sigma_m = 0.02;
  YawAndDrive down_the_axis;
  down_the_axis.velocity_w = Eigen::Vector3d(1.0, 0.0, 0.0);
  down_the_axis.yaw_rate_rad_s = 0.0;
  const RunSummary corridor =
      run(down_the_axis, params, test::full_or_coarse(1.5, 1.2), small_lidar(), test::make_corridor());
  std::size_t on_map = 0, with_prior = 0;
  double previous_var_x = 0;
  for (const ScanResult& r : corridor.results) {
    if (r.map_initialised || !r.registered) continue;
    ++on_map;
    const double var_x = r.covariance_published(0, 0);
    if (on_map <= params.unobserved.window_scans) {
      EXPECT_TRUE(r.prediction_prior) << r.scan_index;  // ICP runs before its scan enters the window
      ++with_prior;
    } else {
      EXPECT_FALSE(r.prediction_prior) << r.scan_index;
    }
    if (on_map < params.unobserved.window_scans) {
      EXPECT_TRUE(r.weak_translation_predicted) << r.scan_index;
      EXPECT_LE(var_x, 2 * 0.02 * 0.02 * on_map) << r.scan_index;  // the prediction's, at most
      EXPECT_GT(var_x, previous_var_x) << r.scan_index;             // and growing: x is never pinned
      previous_var_x = var_x;
    } else {
      EXPECT_TRUE(r.direction_unobserved) << r.scan_index;
      EXPECT_GT(std::sqrt(var_x), 0.5) << r.scan_index;  // unobserved: widened by sigma_m (1 m)
    }
  }
  EXPECT_EQ(with_prior, params.unobserved.window_scans);
  EXPECT_GT(on_map, with_prior + 2);

  // In the room every direction is pinned: the scans' own millimetres decide.
  const RunSummary room = run(YawAndDrive{}, params, test::full_or_coarse(1.5, 1.2), small_lidar());
  for (const ScanResult& r : room.results) {
    if (r.map_initialised || !r.registered) continue;
    EXPECT_TRUE(r.prediction_prior) << r.scan_index;
    EXPECT_LT(r.expected_error_m, 0.01) << r.scan_index;
  }
  EXPECT_LT(room.max_translation_error_m, test::kCoarseTests ? 0.03 : 0.01);
}

TEST(Odometry, DeskewingBeatsNoDeskewingUnderFastRotation) {
  YawAndDrive motion;
  motion.yaw_rate_rad_s = 6.0;  // 34 degrees per revolution of the lidar
  motion.velocity_w = Eigen::Vector3d(0.5, 0.0, 0.0);
  const double duration_s = test::full_or_coarse(2.0, 0.9);
  test::RingLidar lidar = small_lidar();
  lidar.columns = test::full_or_coarse(900, 72);  // coarse: two runs must fit the sanitizer budget
  const RunSummary with = run(motion, test_params(true), duration_s, lidar);
  const RunSummary without = run(motion, test_params(false), duration_s, lidar);
  ASSERT_GE(with.results.size(), test::full_or_coarse(10u, 4u));
  ASSERT_EQ(without.results.size(), with.results.size());
  EXPECT_LT(with.max_translation_error_m, test::kCoarseTests ? 0.03 : 0.01);
  EXPECT_LT(with.max_translation_error_m * 3, without.max_translation_error_m);
  EXPECT_LT(with.max_rotation_error_rad * 3, without.max_rotation_error_rad);
}

TEST(Odometry, InjectedClockTimesEveryStage) {
  const YawAndDrive motion;
  double fake_now = 0;
  OdometryParams params = test_params(true);
  // Every reading of the clock advances it by 1 ms: each timed piece takes 1 ms.
  Odometry odometry(params, [&] { return fake_now += 1e-3; });
  const test::Room room = test::make_room();
  for (int k = 0; k <= 75; ++k) odometry.add_imu(motion.imu(k * 0.01));
  for (int s = 5; s < 7; ++s) {
    Scan scan;
    scan.index = static_cast<std::uint64_t>(s);
    scan.points = test::scan_room(room, [&](double ts) { return motion.pose(ts); }, 0.1 * s, small_lidar());
    EXPECT_EQ(odometry.add_scan(scan), 1u);
  }
  ASSERT_TRUE(odometry.last_result().has_value());
  const StageTimings& t = odometry.last_result()->timings;
  const int iterations = odometry.last_result()->iterations;
  EXPECT_TRUE(t.measured);
  ASSERT_GT(iterations, 0);
  constexpr double ms = 1e-3, tolerance = 1e-9;
  EXPECT_NEAR(t.deskew_s, ms, tolerance);
  EXPECT_NEAR(t.downsample_s, ms, tolerance);
  // Two pieces each: for the registered points before ICP, for the map's new
  // points after it.
  EXPECT_NEAR(t.normals_s, 2 * ms, tolerance);
  EXPECT_NEAR(t.weights_s, 2 * ms, tolerance);
  EXPECT_NEAR(t.seen_through_s, ms, tolerance);
  EXPECT_NEAR(t.map_update_s, 2 * ms, tolerance);
  // ICP reads the clock when it starts, then after matching and after solving
  // in every iteration; the stage also covers its start and end.
  EXPECT_NEAR(t.icp_matching_s, iterations * ms, tolerance);
  EXPECT_NEAR(t.icp_solve_s, iterations * ms, tolerance);
  EXPECT_NEAR(t.registration_s, t.icp_matching_s + t.icp_solve_s + 2 * ms, tolerance);
  EXPECT_NEAR(t.fuser_correction_s, ms, tolerance);
  EXPECT_NEAR(t.total_s,
              t.deskew_s + t.downsample_s + t.normals_s + t.weights_s + t.registration_s + t.seen_through_s +
                  t.map_update_s + t.fuser_correction_s,
              tolerance);
}

TEST(Odometry, WaitsForImuCoverageAndDropsScansBeforeInitialisation) {
  const YawAndDrive motion;
  Odometry odometry(test_params(true));
  const test::Room room = test::make_room();
  auto scan_at = [&](double t0, std::uint64_t index) {
    Scan scan;
    scan.index = index;
    scan.points = test::scan_room(room, [&](double ts) { return motion.pose(ts); }, t0, small_lidar());
    return scan;
  };
  // Before the fuser's static window has passed: dropped.
  odometry.add_imu(motion.imu(0.0));
  EXPECT_EQ(odometry.add_scan(scan_at(0.0, 0)), 0u);
  EXPECT_EQ(odometry.stats().scans_before_init, 1u);
  for (int k = 1; k <= 40; ++k) odometry.add_imu(motion.imu(k * 0.01));
  ASSERT_TRUE(odometry.fuser().initialized());
  // IMU up to 0.40 s: a scan ending at 0.4999 s waits, then the IMU sample
  // that covers it processes it.
  EXPECT_EQ(odometry.add_scan(scan_at(0.4, 1)), 0u);
  std::size_t processed = 0;
  for (int k = 41; k <= 50; ++k) processed += odometry.add_imu(motion.imu(k * 0.01));
  EXPECT_EQ(processed, 1u);
  ASSERT_TRUE(odometry.last_result().has_value());
  EXPECT_TRUE(odometry.last_result()->map_initialised);
  EXPECT_GT(odometry.map().size(), test::full_or_coarse(1000u, 300u));
  EXPECT_FALSE(odometry.last_result()->timings.measured);
}

TEST(Odometry, RejectsInconsistentParameters) {
  OdometryParams p;
  p.weights.map_max_sigma_m = 2.0;
  EXPECT_THROW(Odometry{p}, std::invalid_argument);
}

}  // namespace
}  // namespace tumble
