#include "drivers/mti/imu_sample.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace tumble::mti {
namespace {

TEST(ImuSample, AccelerationAndRateOfTurnAreTakenAsSent) {
  MtData2 m;
  m.acceleration_m_s2 = Eigen::Vector3d(1, 2, 3);
  m.rate_of_turn_rad_s = Eigen::Vector3d(-0.1, 0.2, -0.3);
  ImuSample s;
  s.t_s = 42;
  ASSERT_TRUE(fill_imu_sample(m, 0.01, s));
  EXPECT_EQ(s.accel_m_s2, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(s.gyro_rad_s, Eigen::Vector3d(-0.1, 0.2, -0.3));
  EXPECT_EQ(s.t_s, 42);
  EXPECT_FALSE(s.has_orientation);
}

TEST(ImuSample, DeltasBecomeRatesOverTheOutputPeriod) {
  const double period_s = 1.0 / 400;
  const Eigen::Vector3d omega(2.0, -5.0, 9.0);  // rad/s, about 620 deg/s
  const Eigen::AngleAxisd increment(omega.norm() * period_s, omega.normalized());
  const Eigen::Quaterniond dq(increment);
  MtData2 m;
  m.delta_v_m_s = Eigen::Vector3d(0.025, 0, -0.05);
  m.delta_q = std::array<double, 4>{dq.w(), dq.x(), dq.y(), dq.z()};
  ImuSample s;
  ASSERT_TRUE(fill_imu_sample(m, period_s, s));
  EXPECT_TRUE(s.accel_m_s2.isApprox(Eigen::Vector3d(10, 0, -20), 1e-12));
  EXPECT_TRUE(s.gyro_rad_s.isApprox(omega, 1e-12));
  // -q is the same increment.
  m.delta_q = std::array<double, 4>{-dq.w(), -dq.x(), -dq.y(), -dq.z()};
  ASSERT_TRUE(fill_imu_sample(m, period_s, s));
  EXPECT_TRUE(s.gyro_rad_s.isApprox(omega, 1e-12));
  // No rotation at all.
  m.delta_q = std::array<double, 4>{1, 0, 0, 0};
  ASSERT_TRUE(fill_imu_sample(m, period_s, s));
  EXPECT_EQ(s.gyro_rad_s, Eigen::Vector3d::Zero());
}

TEST(ImuSample, RatesWinOverDeltasWhenBothAreSent) {
  MtData2 m;
  m.acceleration_m_s2 = Eigen::Vector3d(1, 1, 1);
  m.rate_of_turn_rad_s = Eigen::Vector3d(0, 0, 1);
  m.delta_v_m_s = Eigen::Vector3d(5, 5, 5);
  m.delta_q = std::array<double, 4>{1, 0, 0, 0};
  ImuSample s;
  ASSERT_TRUE(fill_imu_sample(m, 0.01, s));
  EXPECT_EQ(s.accel_m_s2, Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(s.gyro_rad_s, Eigen::Vector3d(0, 0, 1));
}

TEST(ImuSample, HalfAPairIsNoSample) {
  MtData2 gnss_only;
  gnss_only.gnss_pvt = GnssPvt{};
  gnss_only.sample_time_fine = 5;
  MtData2 accel_only;
  accel_only.acceleration_m_s2 = Eigen::Vector3d::Zero();
  accel_only.delta_q = std::array<double, 4>{1, 0, 0, 0};
  ImuSample s;
  for (const MtData2& m : {gnss_only, accel_only}) {
    EXPECT_FALSE(has_imu_data(m));
    EXPECT_FALSE(fill_imu_sample(m, 0.01, s));
  }
}

TEST(ImuSample, EachClipBitFlagsItsOwnAxis) {
  MtData2 m;
  m.acceleration_m_s2 = Eigen::Vector3d::Zero();
  m.rate_of_turn_rad_s = Eigen::Vector3d::Zero();
  for (int bit = 8; bit <= 13; ++bit) {
    m.status_word = (1u << bit) | kStatusClipAny;
    ImuSample s;
    ASSERT_TRUE(fill_imu_sample(m, 0.01, s));
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(s.accel_saturated[axis], bit == 8 + axis) << bit;
      EXPECT_EQ(s.gyro_saturated[axis], bit == 11 + axis) << bit;
    }
  }
  // Magnetometer clip bits (14..16) and the rest are not IMU saturation.
  m.status_word = 0xFFFFFFFFu & ~(0x3Fu << 8);
  ImuSample s;
  ASSERT_TRUE(fill_imu_sample(m, 0.01, s));
  EXPECT_EQ(s.accel_saturated, (std::array<bool, 3>{}));
  EXPECT_EQ(s.gyro_saturated, (std::array<bool, 3>{}));
}

TEST(ImuSample, QuaternionBecomesTheOrientation) {
  MtData2 m;
  m.acceleration_m_s2 = Eigen::Vector3d::Zero();
  m.rate_of_turn_rad_s = Eigen::Vector3d::Zero();
  m.quaternion = std::array<double, 4>{0.5, 0.5, -0.5, 0.5};  // w x y z
  ImuSample s;
  ASSERT_TRUE(fill_imu_sample(m, 0.01, s));
  EXPECT_TRUE(s.has_orientation);
  EXPECT_EQ(s.orientation.w(), 0.5);
  EXPECT_EQ(s.orientation.x(), 0.5);
  EXPECT_EQ(s.orientation.y(), -0.5);
  EXPECT_EQ(s.orientation.z(), 0.5);
}

}  // namespace
}  // namespace tumble::mti
