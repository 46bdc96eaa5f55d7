// De-skewing a scan taken under a known constant-twist motion recovers the
// static scene, in the lidar frame at the first point's time.
#include "core/deskew.hpp"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <vector>

namespace tumble {
namespace {

struct Motion {
  Eigen::Vector3d v_w{3.5, 0.4, -0.2};
  Eigen::Vector3d omega_l{0.3, -0.8, 11.0};
  Eigen::Isometry3d pose(double t) const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(omega_l.norm() * t, omega_l.normalized()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(0.2, 0.1, 1.0) + v_w * t;
    return T;
  }
};

Trajectory sampled(const Motion& motion, double t0, double t1, double dt) {
  Trajectory trajectory(1024, SpeedUncertaintyParams{});
  for (double t = t0; t <= t1 + 1e-12; t += dt) {
    TrajectorySample s;
    s.t_s = t;
    const Eigen::Isometry3d T = motion.pose(t);
    s.q_wl = Eigen::Quaterniond(T.rotation());
    s.p_w = T.translation();
    s.v_w = motion.v_w;
    s.omega_l = motion.omega_l;
    trajectory.push_back(s);
  }
  return trajectory;
}

// A static scene seen by the moving lidar: each point measured at its own time.
struct SkewedScan {
  std::vector<Eigen::Vector3d> world, measured;
  std::vector<double> times;
};

SkewedScan skewed_scan(const Motion& motion, double t_start, std::size_t n) {
  SkewedScan scan;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coordinate(-20.0, 20.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = t_start + 0.1 * static_cast<double>(i) / static_cast<double>(n);
    const Eigen::Vector3d p_w(coordinate(rng), coordinate(rng), 0.1 * coordinate(rng));
    scan.world.push_back(p_w);
    scan.times.push_back(t);
    scan.measured.push_back(motion.pose(t).inverse() * p_w);
  }
  return scan;
}

TEST(Deskew, RecoversTheStaticSceneUnderConstantTwist) {
  const Motion motion;
  const double t_start = 100.0;
  const Trajectory trajectory = sampled(motion, t_start - 0.05, t_start + 0.15, 0.01);
  const SkewedScan scan = skewed_scan(motion, t_start, 2000);
  std::vector<Eigen::Vector3d> out(scan.measured.size());
  deskew_points(scan.measured, scan.times, t_start, trajectory, out);
  const Eigen::Isometry3d to_first = motion.pose(t_start).inverse();
  double skew_before = 0.0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Eigen::Vector3d expected = to_first * scan.world[i];
    EXPECT_LT((out[i] - expected).norm(), 1e-9) << i;
    skew_before = std::max(skew_before, (scan.measured[i] - expected).norm());
  }
  EXPECT_GT(skew_before, 1.0);  // 11 rad/s over 0.1 s: metres of skew to undo
}

TEST(Deskew, InPlaceGivesTheSameResult) {
  const Motion motion;
  const Trajectory trajectory = sampled(motion, 0.0, 0.2, 0.01);
  SkewedScan scan = skewed_scan(motion, 0.05, 100);
  std::vector<Eigen::Vector3d> out(scan.measured.size());
  deskew_points(scan.measured, scan.times, 0.05, trajectory, out);
  deskew_points(scan.measured, scan.times, 0.05, trajectory, scan.measured);
  for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i], scan.measured[i]);
}

TEST(Deskew, RigidReanchoringOfTheTrajectoryChangesNothing) {
  // What a registration correction does to the trajectory: left-multiply it.
  const Motion motion;
  const Trajectory trajectory = sampled(motion, 0.0, 0.2, 0.01);
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();
  correction.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  correction.translation() = Eigen::Vector3d(5, -3, 2);
  Trajectory moved(1024, SpeedUncertaintyParams{});
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    TrajectorySample s = trajectory[i];
    s.q_wl = Eigen::Quaterniond(correction.rotation()) * s.q_wl;
    s.p_w = correction * s.p_w;
    s.v_w = correction.rotation() * s.v_w;
    moved.push_back(s);
  }
  const SkewedScan scan = skewed_scan(motion, 0.05, 300);
  std::vector<Eigen::Vector3d> a(scan.measured.size()), b(scan.measured.size());
  deskew_points(scan.measured, scan.times, 0.05, trajectory, a);
  deskew_points(scan.measured, scan.times, 0.05, moved, b);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_LT((a[i] - b[i]).norm(), 1e-9);
}

TEST(Deskew, ScanIsDeskewedToItsFirstPointOrOnlyConvertedWhenOff) {
  const Motion motion;
  const Trajectory trajectory = sampled(motion, 0.0, 0.2, 0.01);
  const SkewedScan skewed = skewed_scan(motion, 0.05, 500);
  Scan scan;
  for (std::size_t i = 0; i < skewed.measured.size(); ++i) {
    LidarPoint point;
    point.t_s = skewed.times[i];
    point.x_m = static_cast<float>(skewed.measured[i].x());
    point.y_m = static_cast<float>(skewed.measured[i].y());
    point.z_m = static_cast<float>(skewed.measured[i].z());
    scan.points.push_back(point);
  }
  std::vector<Eigen::Vector3d> out(scan.points.size());
  deskew_scan(scan, trajectory, false, out);
  for (std::size_t i = 0; i < out.size(); ++i) EXPECT_LT((out[i] - skewed.measured[i]).norm(), 1e-5);
  deskew_scan(scan, trajectory, true, out);
  const Eigen::Isometry3d to_first = motion.pose(scan.points.front().t_s).inverse();
  // Float coordinates: ~1e-6 relative on ~30 m.
  for (std::size_t i = 0; i < out.size(); ++i) EXPECT_LT((out[i] - to_first * skewed.world[i]).norm(), 1e-4);
}

TEST(Deskew, PerPointInterpolationEqualsThePoseAtEveryTime) {
  // The per-point path (segment prepared in the reference frame, series
  // sines) against pose_at: 10 ms segments (0.11 rad, the series), 150 ms
  // segments (1.7 rad, std::sin), quaternion signs alternating (slerp takes
  // the short way), and times beyond both ends (extrapolation).
  const Motion motion;
  for (const double dt : {0.01, 0.15}) {
    Trajectory trajectory(1024, SpeedUncertaintyParams{});
    int flip = 1;
    for (double t = 0.0; t <= 0.6 + 1e-12; t += dt) {
      TrajectorySample s;
      s.t_s = t;
      const Eigen::Isometry3d T = motion.pose(t);
      s.q_wl = Eigen::Quaterniond(T.rotation());
      s.q_wl.coeffs() *= flip;
      flip = -flip;
      s.p_w = T.translation();
      s.v_w = motion.v_w;
      s.omega_l = motion.omega_l;
      trajectory.push_back(s);
    }
    const double t_ref = 0.123;
    RelativePoseInterpolator fast(trajectory, t_ref), reference(trajectory, t_ref);
    const Eigen::Vector3d p(12.0, -7.0, 3.0);
    for (double t = -0.05; t < 0.7; t += 0.0007) {
      EXPECT_LT((fast.point_to_reference(t, p) - reference.to_reference(t) * p).norm(), 1e-9) << "dt " << dt << " t " << t;
    }
  }
}

TEST(Deskew, RejectsMismatchedSizes) {
  const Motion motion;
  const Trajectory trajectory = sampled(motion, 0.0, 0.2, 0.01);
  std::vector<Eigen::Vector3d> points(3), out(2);
  std::vector<double> times(3, 0.1);
  EXPECT_THROW(deskew_points(points, times, 0.1, trajectory, out), std::invalid_argument);
}

}  // namespace
}  // namespace tumble
