// The time offset from synthetic rates: the lidar's rotations over 0.1 s
// intervals from the true motion, an IMU at 100 Hz that is mounted turned
// and whose stamps are early by a known offset (tumbled's convention: the
// offset added to the stamps gives the true time).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "tools/calib/rig_gyro.hpp"
#include "tools/calib/rig_time_offset.hpp"

namespace tumble::calib {
namespace {

// Lidar-frame rate: three axes waving at different frequencies.
Eigen::Vector3d rate_l(double t) {
  return {2.0 * std::sin(2.1 * t), 1.5 * std::sin(3.3 * t + 1.0), 1.8 * std::sin(2.7 * t + 2.0)};
}

struct SyntheticRig {
  std::vector<LidarRotation> lidar;
  std::vector<ImuSample> imu;
};

SyntheticRig synthetic_rig(double offset_s, const Eigen::Matrix3d& R_li) {
  SyntheticRig rig;
  // The true rate densely (1 kHz, lidar frame) gives the lidar's rotations.
  std::vector<ImuSample> dense;
  for (int i = 0; i <= 20'000; ++i) {
    ImuSample s;
    s.t_s = i * 0.001;
    s.gyro_rad_s = rate_l(s.t_s);
    dense.push_back(s);
  }
  for (int k = 10; k < 190; ++k) {
    const double t0 = 0.1 * k + 0.0003 * (k % 7), t1 = 0.1 * (k + 1) + 0.0003 * ((k + 1) % 7);
    const Eigen::AngleAxisd turn(gyro_rotation(dense, {}, t0, t1));
    rig.lidar.push_back({t0, t1, turn.angle() * turn.axis()});
  }
  for (int j = 0; j < 2000; ++j) {
    ImuSample s;
    const double t_true = 0.0037 + j * 0.01;
    s.t_s = t_true - offset_s;
    s.gyro_rad_s = R_li.transpose() * rate_l(t_true);
    rig.imu.push_back(s);
  }
  return rig;
}

const Eigen::Matrix3d kR_li = (Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();

TEST(RigTimeOffset, CrossCorrelationFindsTheOffsetToTheMillisecond) {
  for (const double offset_s : {0.0123, -0.0871}) {
    const SyntheticRig rig = synthetic_rig(offset_s, kR_li);
    // ±0.1 s holds both offsets; each millisecond searched costs a pass over the rig (43 s under ASan at ±0.3 s).
    const TimeOffsetEstimate coarse = coarse_time_offset(rig.lidar, rig.imu, 0.0, 0.1, 0.001);
    EXPECT_FALSE(coarse.at_edge);
    EXPECT_NEAR(coarse.offset_s, offset_s, 0.001) << offset_s;
    EXPECT_GT(coarse.score, 0.99);
  }
}

TEST(RigTimeOffset, FineSearchFindsItToATenthOfAMillisecond) {
  const double offset_s = 0.0123;
  const SyntheticRig rig = synthetic_rig(offset_s, kR_li);
  const TimeOffsetEstimate fine = fine_time_offset(rig.lidar, rig.imu, 0.012, 0.002, 0.0002);
  EXPECT_FALSE(fine.at_edge);
  EXPECT_NEAR(fine.offset_s, offset_s, 0.0001);
  const HandEyeRotation at_fine = align_rotation_increments(rotation_increments(rig.lidar, rig.imu, fine.offset_s));
  EXPECT_LT(Eigen::AngleAxisd(at_fine.R_li.transpose() * kR_li).angle(), 0.001);
}

TEST(RigTimeOffset, AnOffsetBeyondTheSearchIsReportedAtTheEdge) {
  const SyntheticRig rig = synthetic_rig(0.2, kR_li);
  EXPECT_TRUE(coarse_time_offset(rig.lidar, rig.imu, 0.0, 0.1, 0.001).at_edge);
}

}  // namespace
}  // namespace tumble::calib
