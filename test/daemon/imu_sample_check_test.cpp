// Numbers that are no measurement never reach the fuser: NaN, Inf, or an
// axis beyond what the device can read, rejected and counted.
#include "daemon/imu_sample_check.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "daemon/imu_parts.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_encode.hpp"
#include "drivers/mti/xbus_frame.hpp"
#include "test/daemon/captured_log.hpp"

namespace tumble::daemon {
namespace {

constexpr ImuLimits kMti30{7.85, 200.0};
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

ImuSample still() {
  ImuSample s;
  s.t_s = 1.0;
  s.accel_m_s2 = {0.0, 0.0, 9.81};
  return s;
}

TEST(ImuSampleCheck, AStillSampleAndAClippedOneAreMeasurements) {
  EXPECT_EQ(check_imu_sample(still(), kMti30), ImuSampleFault::None);
  ImuSample clipped = still();
  clipped.gyro_rad_s.z() = -10.33;  // a real capture of a clipped 450 deg/s gyro (docs/sensors.md)
  clipped.gyro_saturated[2] = true;
  EXPECT_EQ(check_imu_sample(clipped, kMti30), ImuSampleFault::None);
}

TEST(ImuSampleCheck, NaNAndInfAnywhereAreRejected) {
  ImuSample s = still();
  s.gyro_rad_s.x() = kNaN;
  EXPECT_EQ(check_imu_sample(s, kMti30), ImuSampleFault::NotFinite);
  s = still();
  s.accel_m_s2.y() = -kInf;
  EXPECT_EQ(check_imu_sample(s, kMti30), ImuSampleFault::NotFinite);
  s = still();
  s.t_s = kNaN;
  EXPECT_EQ(check_imu_sample(s, kMti30), ImuSampleFault::NotFinite);
  s = still();
  s.has_orientation = true;
  s.orientation.w() = kNaN;
  EXPECT_EQ(check_imu_sample(s, kMti30), ImuSampleFault::NotFinite);
}

TEST(ImuSampleCheck, AxesBeyondTheRangesMarginAndABrokenQuaternionAreRejected) {
  ImuSample s = still();
  s.gyro_rad_s.y() = 1.01 * kClippedOvershoot * kMti30.gyro_range_rad_s;
  EXPECT_EQ(check_imu_sample(s, kMti30), ImuSampleFault::BeyondRange);
  s = still();
  s.accel_m_s2.x() = -1.01 * kClippedOvershoot * kMti30.accel_range_m_s2;
  EXPECT_EQ(check_imu_sample(s, kMti30), ImuSampleFault::BeyondRange);
  s = still();
  s.has_orientation = true;
  s.orientation.coeffs() << 0.0, 0.0, 0.0, 2.0;
  EXPECT_EQ(check_imu_sample(s, kMti30), ImuSampleFault::BadOrientation);
}

std::vector<std::uint8_t> frame(std::uint16_t counter, const Eigen::Vector3d& gyro_rad_s) {
  mti::MtData2Out m;
  m.packet_counter = counter;
  m.sample_time_fine = 100u * counter;  // 100 Hz
  m.accel_m_s2 = {0.0, 0.0, 9.81};
  m.gyro_rad_s = gyro_rad_s;
  return mti::encode_xbus_frame(mti::mid::kMtData2, mti::encode_mtdata2(m));
}

TEST(ImuSampleCheck, TheDecoderPassesOnlyMeasurementsAndCountsAndNamesTheRest) {
  const CapturedLog log;
  MtiByteDecoder decoder(ImuConfig{});
  std::vector<ImuSample> fused;
  const auto emit = [&](const ImuSample& s) { fused.push_back(s); };
  for (std::uint16_t i = 1; i <= 20; ++i) {
    // Sample 7 carries a NaN, sample 12 a rate no MTi reads (40 rad/s).
    Eigen::Vector3d gyro(0.01, 0.0, 0.0);
    if (i == 7) gyro.x() = kNaN;
    if (i == 12) gyro.z() = 40.0;
    const std::vector<std::uint8_t> bytes = frame(i, gyro);
    decoder.decode(ImuBytes{1000.0 + 0.01 * i, bytes}, emit);
  }
  ASSERT_EQ(fused.size(), 18u);
  for (const ImuSample& s : fused) EXPECT_EQ(check_imu_sample(s, kMti30), ImuSampleFault::None);
  PipelineCounters counters;
  decoder.report(counters);
  EXPECT_EQ(counters.imu_rejected_samples.load(), 2);
  const std::string text = log.text();
  EXPECT_NE(text.find("warning imu: sample rejected (NaN or Inf): gyro [nan, 0, 0] rad/s"), std::string::npos)
      << text;
  EXPECT_EQ(text.find("2 so far"), std::string::npos) << "not rate-limited:\n" << text;
}

}  // namespace
}  // namespace tumble::daemon
