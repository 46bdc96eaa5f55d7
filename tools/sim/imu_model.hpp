// The MTi-30 as a sensor: what its accelerometer and gyroscope read at each
// sample (lever arm, gravity, noise, bias, clipping) and its own sample clock
// (SampleTimeFine drifting against host time).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

#include "tools/sim/motion.hpp"
#include "tools/sim/sensor_rng.hpp"

namespace tumble::sim {

// MTi-30 (MT0605P) values as defaults.
struct ImuConfig {
  int rate_hz = 100;                                // a divisor of 400 (the device's base rate)
  double gyro_noise_density_deg_s_sqrt_hz = 0.03;
  double accel_noise_density_ug_sqrt_hz = 60.0;
  double gyro_initial_bias_sigma_deg_s = 0.2;       // turn-on bias, 1 sigma per axis
  double accel_initial_bias_sigma_m_s2 = 0.02;
  // Bias random walk, given as the 1-sigma wander after 100 s: the datasheet's
  // in-run bias stability is that level.
  double gyro_bias_stability_deg_h = 18.0;
  double accel_bias_stability_ug = 15.0;
  double gyro_range_deg_s = 450.0;
  double accel_range_m_s2 = 200.0;
};

// The device clock of one run.
struct ImuClock {
  double drift_ppm = 0.0;                 // device seconds run (1 + ppm 1e-6) times host seconds
  double first_sample_s = 0.0;            // run time of the first sample
  std::uint32_t first_sample_time_fine = 0;  // its SampleTimeFine (10 kHz ticks since power-up)
  std::uint16_t first_packet_counter = 0;
  // The rig's lidar-IMU time offset, in tumbled's convention: the sample sent
  // (and so stamped) at run time t measures the motion at t + this, so
  // tumbled's `imu.imu_time_offset_s` set to the same value cancels it.
  double imu_time_offset_s = 0.0;
};

// StatusWord clip bits (mti.md).
inline constexpr std::uint32_t kStatusAccelClipX = 1u << 8;
inline constexpr std::uint32_t kStatusGyroClipX = 1u << 11;
inline constexpr std::uint32_t kStatusAnyClip = 1u << 19;

// What an ideal IMU at pose T_LI on the body reads: specific force and angular
// rate in the IMU frame. a_imu = a_body + alpha x r + omega x (omega x r).
struct ImuKinematics {
  Eigen::Vector3d specific_force_i;
  Eigen::Vector3d omega_i;
};
ImuKinematics imu_kinematics(const MotionState& body, const Eigen::Isometry3d& T_LI);

struct ImuMeasurement {
  double t_s = 0.0;  // run time the sample is sent for (it measures the motion at t_s + imu_time_offset_s)
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();  // as reported (clipped at the range)
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  std::uint32_t status_word = 0;
  std::uint32_t sample_time_fine = 0;
  std::uint16_t packet_counter = 0;
};

class ImuModel {
 public:
  // noise_enabled = false gives the ideal readings (bias, noise and bias walk
  // off), still clipped at the range like the device.
  ImuModel(const ImuConfig& config, const ImuClock& clock, const Eigen::Isometry3d& T_LI, const Motion& motion,
           std::uint64_t noise_seed, bool noise_enabled);

  // The k-th sample; false once past duration_s.
  bool next(double duration_s, ImuMeasurement& out);

  const Eigen::Vector3d& initial_gyro_bias_rad_s() const { return initial_gyro_bias_; }
  const Eigen::Vector3d& initial_accel_bias_m_s2() const { return initial_accel_bias_; }

 private:
  Eigen::Vector3d gaussian3(double sigma);

  ImuConfig config_;
  ImuClock clock_;
  Eigen::Isometry3d T_LI_;
  const Motion& motion_;
  SensorRng rng_;
  bool noise_enabled_;
  std::uint64_t index_ = 0;
  Eigen::Vector3d gyro_bias_, accel_bias_;
  Eigen::Vector3d initial_gyro_bias_, initial_accel_bias_;
};

// Sample k's run time under the device clock: samples are evenly spaced in
// device time, so host-time spacing is period / (1 + drift).
double imu_sample_time_s(const ImuClock& clock, int rate_hz, std::uint64_t k);

}  // namespace tumble::sim
