// tumble-eval imu on the real MTi-G-710 recordings (fixtures) and on
// constructed up vectors.
#include "tools/eval/imu_attitude.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <string>

#include "test/fixtures.hpp"
#include "test/temp_dir.hpp"

namespace tumble::eval {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(ImuAttitude, RollAndPitchOfUpVectors) {
  EXPECT_NEAR(roll_pitch_rad(Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
  // Rolled by +30 deg about x (R_ws = Rx(30)): the world's up, seen in the sensor, is Rx(-30) z.
  const Eigen::Vector3d rolled = Eigen::AngleAxisd(-30 * kDeg, Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(roll_pitch_rad(rolled).x(), 30 * kDeg, 1e-12);
  EXPECT_NEAR(roll_pitch_rad(rolled).y(), 0.0, 1e-12);
  EXPECT_NEAR(tilt_between_deg(rolled, Eigen::Vector3d::UnitZ()), 30.0, 1e-9);
  EXPECT_NEAR(tilt_between_deg(2.0 * rolled, rolled), 0.0, 1e-9);
}

// Recordings 1-4 carry Acceleration and RateOfTurn (5 has neither: no IMU samples).
class EinrideRecording : public ::testing::TestWithParam<int> {};

TEST_P(EinrideRecording, TiltAgainstTheStillAccelerometerIsWithinOneDegree) {
  const std::string file = "mti/einride-mti-g-710/" + std::to_string(GetParam()) + "/output.bin";
  TUMBLE_REQUIRE_FIXTURE(file);
  ImuEvalOptions options;
  const ImuEvaluation e = evaluate_imu_recording(::tumble::test::fixture_path(file), options);
  EXPECT_EQ(e.reader_problem, "");
  ASSERT_GT(e.samples, 90u);
  ASSERT_EQ(e.still_periods.size(), 1u);  // the unit lies still for the whole second
  ASSERT_TRUE(e.initialized_at_s.has_value());
  ASSERT_TRUE(e.ours_vs_accel.has_value());
  EXPECT_GT(e.ours_vs_accel->count, 30u);
  EXPECT_LE(e.ours_vs_accel->median_deg, 1.0);
  ASSERT_TRUE(e.still_periods[0].entry_tilt_deg.has_value());  // the fuser initialised inside it
  EXPECT_LT(*e.still_periods[0].entry_tilt_deg, 1.0);
  // The device's own filter (Euler angles here) is compared too.
  ASSERT_TRUE(e.device_vs_accel.has_value());
  ASSERT_TRUE(e.ours_vs_device.has_value());
  EXPECT_LT(e.ours_vs_device->median_deg, 2.0);
  // The bias from the fuser's window is the still gyro's mean (within its noise).
  EXPECT_LT((e.fuser_gyro_bias_rad_s - e.still_periods[0].mean_gyro_rad_s).norm(), 0.002);
  EXPECT_EQ(e.samples_clipped, 0u);
}

INSTANTIATE_TEST_SUITE_P(Fixtures, EinrideRecording, ::testing::Values(1, 2, 3, 4));

TEST(ImuAttitude, WritesTumAndAReport) {
  const std::string file = "mti/einride-mti-g-710/1/output.bin";
  TUMBLE_REQUIRE_FIXTURE(file);
  const ImuEvaluation e = evaluate_imu_recording(::tumble::test::fixture_path(file), ImuEvalOptions{});
  const test::TempDir dir;
  write_attitude_tum(e, dir.path() / "attitude.tum");
  std::ifstream in(dir.path() / "attitude.tum");
  std::size_t rows = 0;
  for (std::string line; std::getline(in, line);) rows += !line.empty() && line[0] != '#';
  EXPECT_EQ(rows, e.attitude.size());
  const std::string report = imu_report_markdown(e);
  EXPECT_NE(report.find("ours vs still accelerometer | " + std::to_string(e.ours_vs_accel->count)), std::string::npos)
      << report;
  EXPECT_NE(report.find("0 samples clipped"), std::string::npos) << report;
}

TEST(ImuAttitude, ARecordingWithoutImuSamplesIsReportedNotFailed) {
  const std::string file = "mti/einride-mti-g-710/5/output.bin";
  TUMBLE_REQUIRE_FIXTURE(file);
  const ImuEvaluation e = evaluate_imu_recording(::tumble::test::fixture_path(file), ImuEvalOptions{});
  EXPECT_EQ(e.samples, 0u);
  EXPECT_FALSE(e.initialized_at_s.has_value());
  EXPECT_NE(imu_report_markdown(e).find("never initialised"), std::string::npos);
}

}  // namespace
}  // namespace tumble::eval
