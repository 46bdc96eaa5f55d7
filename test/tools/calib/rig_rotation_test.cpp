// The hand-eye rotation from synthetic rotation increments with a known
// R_LI, gyro bias, noise and a few bad registrations.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "core/angles.hpp"
#include "tools/calib/rig_rotation.hpp"

namespace tumble::calib {
namespace {

Eigen::Matrix3d rpy_deg(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw * kDegToRad, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch * kDegToRad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll * kDegToRad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

struct Synthetic {
  std::vector<RotationIncrement> increments;
  std::vector<bool> corrupted;
};

Synthetic synthetic(const Eigen::Matrix3d& R_li, const Eigen::Vector3d& bias_rad_s, double noise_rad,
                    int corrupt_every) {
  std::mt19937 rng(7);
  std::normal_distribution<double> turn(0.0, 0.15), noise(0.0, noise_rad);
  Synthetic s;
  for (int k = 0; k < 300; ++k) {
    const double dt = 0.1;
    const Eigen::Vector3d r_true_i(turn(rng), turn(rng), turn(rng));
    Eigen::Vector3d r_l = R_li * r_true_i + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    const bool corrupt = corrupt_every > 0 && k % corrupt_every == 0;
    if (corrupt) r_l += Eigen::Vector3d(0.1, -0.08, 0.05);  // a registration gone wrong
    s.increments.push_back({r_l, r_true_i + bias_rad_s * dt, dt});
    s.corrupted.push_back(corrupt);
  }
  return s;
}

double angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * kRadToDeg;
}

TEST(RigRotation, RecoversAnUpsideDownQuarterTurnedMountAndTheGyroBias) {
  const Eigen::Matrix3d R_li = rpy_deg(180, 0, 90);
  const Eigen::Vector3d bias(0.004, -0.003, 0.006);
  const Synthetic s = synthetic(R_li, bias, 0.0005, 0);
  const HandEyeRotation fit = align_rotation_increments(s.increments);
  EXPECT_LT(angle_deg(fit.R_li, R_li), 0.02);
  EXPECT_LT((fit.gyro_bias_rad_s - bias).norm(), 0.001);
  EXPECT_EQ(fit.used, s.increments.size());
  // σ from the residuals: the 0.0005 rad noise over 300 increments of ~0.26 rad.
  EXPECT_GT(fit.sigma_deg, 0.001);
  EXPECT_LT(fit.sigma_deg, 0.02);
  EXPECT_NEAR(fit.rms_residual_rad, 0.0005, 0.0001);
}

TEST(RigRotation, LeavesOutBadRegistrationsUnlessAskedToKeepEveryIncrement) {
  const Eigen::Matrix3d R_li = rpy_deg(10, -20, 35);
  const Synthetic s = synthetic(R_li, Eigen::Vector3d::Zero(), 0.0005, 10);
  const HandEyeRotation robust = align_rotation_increments(s.increments);
  EXPECT_LT(angle_deg(robust.R_li, R_li), 0.02);
  for (std::size_t k = 0; k < s.increments.size(); ++k) EXPECT_EQ(robust.inlier[k], !s.corrupted[k]) << k;
  const HandEyeRotation all = align_rotation_increments(s.increments, false);
  EXPECT_EQ(all.used, s.increments.size());
  EXPECT_GT(angle_deg(all.R_li, R_li), 0.1);  // the bad ones pull it off
}

TEST(RigRotation, TurningAboutOneAxisOnlyIsNotEnough) {
  std::vector<RotationIncrement> about_z;
  for (int k = 0; k < 50; ++k) about_z.push_back({Eigen::Vector3d(0, 0, 0.1 * (k % 5)), Eigen::Vector3d(0, 0, 0.1), 0.1});
  EXPECT_LT(weakest_axis_excitation_rad2(about_z), 1e-12);
  EXPECT_EQ(align_rotation_increments(about_z).used, 0u);
}

}  // namespace
}  // namespace tumble::calib
