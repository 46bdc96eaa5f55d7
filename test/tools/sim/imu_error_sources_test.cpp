// The MTi-30 error sources beyond noise and bias (ImuConfig): each is absent
// when off, and when on its statistic over many runs has the configured
// (datasheet) magnitude. One run draws one value per axis, so the spread is
// measured across seeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/types.hpp"
#include "core/angles.hpp"
#include "test/tools/sim/sensor_test_support.hpp"
#include "tools/sim/imu_model.hpp"

namespace tumble::sim {
namespace {

using test::SpinMotion;

constexpr int kSeeds = 400;

struct Spread {
  double mean = 0.0, sigma = 0.0;
};

Spread spread(const std::vector<double>& v) {
  double sum = 0.0, sq = 0.0;
  for (const double x : v) sum += x;
  const double mean = sum / static_cast<double>(v.size());
  for (const double x : v) sq += (x - mean) * (x - mean);
  return {mean, std::sqrt(sq / static_cast<double>(v.size() - 1))};
}

// 400 draws: the sample sigma is within 10 % of the true one with > 99 % odds.
void expect_sigma(const std::vector<double>& draws, double sigma) {
  const Spread s = spread(draws);
  EXPECT_NEAR(s.sigma, sigma, 0.12 * sigma);
  EXPECT_NEAR(s.mean, 0.0, 4.0 * sigma / std::sqrt(static_cast<double>(draws.size())));
}

ImuClock clock_at_zero() {
  ImuClock c;
  c.first_sample_time_fine = 10'000;
  return c;
}

// The first sample of an IMU at the origin of a motion, noise off.
ImuMeasurement first_sample(const ImuConfig& config, const Motion& motion, std::uint64_t seed) {
  ImuModel model(config, clock_at_zero(), Eigen::Isometry3d::Identity(), motion, seed, false);
  ImuMeasurement m;
  EXPECT_TRUE(model.next(motion.duration_s(), m));
  return m;
}

TEST(ImuErrorSources, AllOffByDefaultGiveTheIdealReadings) {
  const ImuUnitErrors e = draw_imu_unit_errors(ImuConfig{}, 5);
  EXPECT_EQ(e.gyro_sensing, Eigen::Matrix3d::Identity());
  EXPECT_EQ(e.accel_sensing, Eigen::Matrix3d::Identity());
  EXPECT_EQ(e.gyro_g_sensitivity_rad_s_per_m_s2, Eigen::Matrix3d::Zero());
  EXPECT_EQ(e.gyro_warm_up_drift_rad_s, Eigen::Vector3d::Zero());
  const SpinMotion spin({0, 0, 1}, 2.0, 1.0);
  const ImuMeasurement m = first_sample(ImuConfig{}, spin, 5);
  // The mean of the period's 10 kHz sub-samples: equal up to rounding.
  EXPECT_LT((m.gyro_rad_s - Eigen::Vector3d(0, 0, 2.0)).norm(), 1e-12);
  EXPECT_LT((m.accel_m_s2 - Eigen::Vector3d(0, 0, kStandardGravity_m_s2)).norm(), 1e-12);
}

TEST(ImuErrorSources, ScaleFactorErrorHasTheDatasheetSigma) {
  ImuConfig config;
  config.scale_factor_error = true;
  const SpinMotion spin({0, 0, 1}, 2.0, 1.0);
  std::vector<double> gyro_gain_error, accel_gain_error;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
    const ImuMeasurement m = first_sample(config, spin, seed);
    gyro_gain_error.push_back(m.gyro_rad_s.z() / 2.0 - 1.0);
    accel_gain_error.push_back(m.accel_m_s2.z() / kStandardGravity_m_s2 - 1.0);
    EXPECT_EQ(m.gyro_rad_s.x(), 0.0);  // a gain error alone does not mix axes
  }
  expect_sigma(gyro_gain_error, 0.03e-2);
  expect_sigma(accel_gain_error, 0.1e-2);
}

TEST(ImuErrorSources, MisalignmentLeaksEachAxisIntoTheOthers) {
  ImuConfig config;
  config.misalignment = true;
  const SpinMotion spin({0, 0, 1}, 2.0, 1.0);
  std::vector<double> gyro_leak, accel_leak;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
    const ImuMeasurement m = first_sample(config, spin, seed);
    EXPECT_EQ(m.gyro_rad_s.z(), 2.0);  // the axis itself keeps its gain
    gyro_leak.push_back(m.gyro_rad_s.x() / 2.0);
    accel_leak.push_back(m.accel_m_s2.y() / kStandardGravity_m_s2);
  }
  expect_sigma(gyro_leak, 0.05 * kDegToRad);
  expect_sigma(accel_leak, 0.05 * kDegToRad);
}

TEST(ImuErrorSources, GSensitivityTurnsGravityIntoARate) {
  ImuConfig config;
  config.g_sensitivity = true;
  const SpinMotion still({0, 0, 1}, 0.0, 1.0);
  std::vector<double> rate_per_g;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
    const ImuMeasurement m = first_sample(config, still, seed);
    for (int axis = 0; axis < 3; ++axis) rate_per_g.push_back(m.gyro_rad_s[axis] / kDegToRad);
  }
  expect_sigma(rate_per_g, 0.006);  // deg/s at 1 g
}

TEST(ImuErrorSources, TemperatureDriftMovesTheBiasOverTheWarmUp) {
  ImuConfig config;
  config.rate_hz = 1;
  config.temperature_drift = true;
  // The drawn offsets' spread, over many units.
  std::vector<double> gyro_drift_deg_s, accel_drift_m_s2;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
    const ImuUnitErrors e = draw_imu_unit_errors(config, seed);
    gyro_drift_deg_s.push_back(e.gyro_warm_up_drift_rad_s.x() / kDegToRad);
    accel_drift_m_s2.push_back(e.accel_warm_up_drift_m_s2.x());
  }
  expect_sigma(gyro_drift_deg_s, 0.2);
  expect_sigma(accel_drift_m_s2, 0.02);
  // The readings approach them over the warm-up (a few units: simulating
  // 600 s of every unit costs minutes under ASan).
  const SpinMotion still({0, 0, 1}, 0.0, 700.0);
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    ImuModel model(config, clock_at_zero(), Eigen::Isometry3d::Identity(), still, seed, false);
    ImuMeasurement m;
    std::vector<ImuMeasurement> samples;
    while (model.next(600.0, m)) samples.push_back(m);
    ASSERT_EQ(samples.size(), 601u);
    EXPECT_LT(samples[0].gyro_rad_s.norm(), 1e-12);  // cold at the start
    const ImuUnitErrors& e = model.unit_errors();
    EXPECT_EQ(e.gyro_warm_up_drift_rad_s, draw_imu_unit_errors(config, seed).gyro_warm_up_drift_rad_s);
    EXPECT_NE(e.gyro_warm_up_drift_rad_s, Eigen::Vector3d::Zero());
    // One time constant in: 1 - 1/e of the way; two: 1 - 1/e².
    EXPECT_LT((samples[300].gyro_rad_s - (1.0 - std::exp(-1.0)) * e.gyro_warm_up_drift_rad_s).norm(), 1e-12);
    const Eigen::Vector3d gravity(0, 0, kStandardGravity_m_s2);
    EXPECT_LT((samples[600].accel_m_s2 - gravity - (1.0 - std::exp(-2.0)) * e.accel_warm_up_drift_m_s2).norm(), 1e-12);
  }
}

// Spin up at a constant angular acceleration: the rate read is a clock.
class SpinUp final : public Motion {
 public:
  MotionState at(double t_s) const override {
    MotionState s;
    s.T_wb = Eigen::Isometry3d(Eigen::AngleAxisd(0.5 * kRate * t_s * t_s, Eigen::Vector3d::UnitZ()));
    s.omega_b = Eigen::Vector3d(0, 0, kRate * t_s);
    s.alpha_b = Eigen::Vector3d(0, 0, kRate);
    return s;
  }
  double duration_s() const override { return 10.0; }
  static constexpr double kRate = 2.0;  // rad/s^2
};

TEST(ImuErrorSources, TimestampJitterIsUniformOverHalfATick) {
  const SpinUp motion;
  for (const bool on : {false, true}) {
    ImuConfig config;
    config.rate_hz = 400;
    config.timestamp_jitter = on;
    ImuModel model(config, clock_at_zero(), Eigen::Isometry3d::Identity(), motion, 3, false);
    ImuMeasurement m;
    std::vector<double> late_s;
    // Up to 2 s: 4 rad/s, inside the gyro's range.
    while (model.next(2.0, m)) late_s.push_back(m.gyro_rad_s.z() / SpinUp::kRate - m.t_s);
    ASSERT_EQ(late_s.size(), 801u);
    const Spread s = spread(late_s);
    if (!on) {
      EXPECT_LT(s.sigma, 1e-12);
      continue;
    }
    for (const double l : late_s) EXPECT_LE(std::abs(l), 50e-6 + 1e-12);
    EXPECT_NEAR(s.sigma, 50e-6 / std::sqrt(3.0), 0.05 * 50e-6 / std::sqrt(3.0));
    EXPECT_NEAR(s.mean, 0.0, 4e-6);
  }
}

TEST(ImuErrorSources, EachSourceDrawsFromItsOwnStreamAndASeedRepeats) {
  ImuConfig one;
  one.g_sensitivity = true;
  ImuConfig all = one;
  all.scale_factor_error = all.misalignment = all.temperature_drift = all.timestamp_jitter = true;
  EXPECT_EQ(draw_imu_unit_errors(one, 7).gyro_g_sensitivity_rad_s_per_m_s2,
            draw_imu_unit_errors(all, 7).gyro_g_sensitivity_rad_s_per_m_s2);
  EXPECT_EQ(draw_imu_unit_errors(all, 7).gyro_sensing, draw_imu_unit_errors(all, 7).gyro_sensing);
  EXPECT_NE(draw_imu_unit_errors(all, 7).gyro_sensing, draw_imu_unit_errors(all, 8).gyro_sensing);
}

// Straight along x at a constant speed: no acceleration, no rotation.
class CruiseMotion final : public Motion {
 public:
  explicit CruiseMotion(double speed_m_s) : speed_(speed_m_s) {}
  MotionState at(double t_s) const override {
    MotionState s;
    s.T_wb.translation() = Eigen::Vector3d(speed_ * t_s, 0.0, 1.0);
    s.v_w = Eigen::Vector3d(speed_, 0.0, 0.0);
    return s;
  }
  double duration_s() const override { return 10.0; }

 private:
  double speed_;
};

// Each axis of the carrier's vibration has unit RMS, the sum of its
// kVibrationModes sinusoids of amplitude sqrt(2 / modes).
TEST(ImuVibration, EachAxisOscillatesWithUnitRms) {
  const CarrierVibration vibration = draw_carrier_vibration(7);
  for (const auto* axes : {&vibration.accel, &vibration.gyro}) {
    for (const VibrationAxis& axis : *axes) {
      double squares = 0.0, peak = 0.0;
      const int samples = 100'000;  // 100 s, every ms: the 20 Hz mode 2000 times over
      for (int i = 0; i < samples; ++i) {
        const double value = axis.at(i * 1e-3);
        squares += value * value;
        peak = std::max(peak, std::abs(value));
      }
      EXPECT_NEAR(std::sqrt(squares / samples), 1.0, 0.05);
      EXPECT_LE(peak, std::sqrt(2.0 * kVibrationModes));
      for (const double omega_rad_s : axis.omega_rad_s) {
        EXPECT_GE(omega_rad_s, 2.0 * std::numbers::pi * kVibrationLowest_hz);
        EXPECT_LE(omega_rad_s, 2.0 * std::numbers::pi * kVibrationHighest_hz);
      }
    }
  }
}

// The vibration is an oscillation sensed at 10 kHz and averaged over each
// period, as the device's strapdown integration does: a sample shows some of
// it, but consecutive samples take back what the one before added, so the
// velocity and angle integrated from the samples stay within the
// oscillation's own (a random walk per sample grew without bound).
TEST(ImuVibration, GrowsWithSpeedIsNothingAtRestAndIntegratesToNoDrift) {
  ImuConfig on;
  on.vibration = true;
  for (const double speed_m_s : {0.0, 2.0}) {
    const CruiseMotion motion(speed_m_s);
    ImuModel with(on, clock_at_zero(), Eigen::Isometry3d::Identity(), motion, 3, false);
    ImuModel without(ImuConfig{}, clock_at_zero(), Eigen::Isometry3d::Identity(), motion, 3, false);
    std::vector<double> accel, gyro;
    Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero(), angle_rad = Eigen::Vector3d::Zero();
    double largest_velocity_m_s = 0.0, largest_angle_rad = 0.0;
    ImuMeasurement a, b;
    const double period_s = 1.0 / on.rate_hz;
    while (with.next(motion.duration_s(), a)) {
      ASSERT_TRUE(without.next(motion.duration_s(), b));
      for (int axis = 0; axis < 3; ++axis) {
        accel.push_back(a.accel_m_s2[axis] - b.accel_m_s2[axis]);
        gyro.push_back(a.gyro_rad_s[axis] - b.gyro_rad_s[axis]);
      }
      velocity_m_s += (a.accel_m_s2 - b.accel_m_s2) * period_s;
      angle_rad += (a.gyro_rad_s - b.gyro_rad_s) * period_s;
      largest_velocity_m_s = std::max(largest_velocity_m_s, velocity_m_s.cwiseAbs().maxCoeff());
      largest_angle_rad = std::max(largest_angle_rad, angle_rad.cwiseAbs().maxCoeff());
    }
    ASSERT_GE(accel.size(), 3000u);
    if (speed_m_s == 0.0) {
      for (const double d : accel) EXPECT_EQ(d, 0.0);
      for (const double d : gyro) EXPECT_EQ(d, 0.0);
      continue;
    }
    const double accel_sigma_m_s2 = 3.0 * speed_m_s, gyro_sigma_rad_s = 1.0 * speed_m_s * kDegToRad;
    // Some of it in each sample: the modes below the 100 Hz output rate pass.
    EXPECT_GT(spread(accel).sigma, 0.05 * accel_sigma_m_s2);
    EXPECT_LT(spread(accel).sigma, accel_sigma_m_s2);
    EXPECT_GT(spread(gyro).sigma, 0.05 * gyro_sigma_rad_s);
    // A mode's velocity is its amplitude over its angular frequency: the
    // modes together reach at most sqrt(2 modes) sigma / (2 pi lowest
    // frequency), and the integral from the start spans twice that.
    const double bound_s =
        2.0 * std::sqrt(2.0 * kVibrationModes) / (2.0 * std::numbers::pi * kVibrationLowest_hz);
    EXPECT_LT(largest_velocity_m_s, bound_s * accel_sigma_m_s2);  // white noise per sample: ~2 m/s after 10 s
    EXPECT_LT(largest_angle_rad, bound_s * gyro_sigma_rad_s);
  }
}

}  // namespace
}  // namespace tumble::sim
