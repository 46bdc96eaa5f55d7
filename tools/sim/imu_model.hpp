// The MTi-30 as a sensor: what its accelerometer and gyroscope read at each
// sample (lever arm, gravity, noise, bias, clipping) and its own sample clock
// (SampleTimeFine drifting against host time).
//
// A sample is the mean over its output period, not the motion at an instant:
// the unit samples its sensors at 10 kHz and its calibrated acceleration and
// rate of turn "have been going through Strapdown Integration and Inverse
// Strapdown Integration" (MT0605P, calibrated inertial data outputs), i.e.
// they are the velocity and attitude increments over the period divided by
// it, which Xsens states lose no information at any output rate (the mean
// of body-frame sub-samples leaves out the coning and sculling terms: about
// (ωT)²/24 of the reading, 3e-4 at the gyro's range and 100 Hz). An impact
// shorter than the period shows as its net change, as on the device; sampled
// at an instant, a 4 ms jolt of the cage read 140 m/s² for a whole 10 ms
// period, 1.4 m/s of velocity the cage never had. Each 10 kHz sub-sample is
// clipped at the range (the flag says some were), then averaged (at most
// 100 sub-samples: below 100 Hz, which only tests use, they are spaced
// wider). The period is centred on the sample's time: where in it the stamp
// falls is not documented, and centred it adds no delay to the rig's
// declared offset.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
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

  // Error sources a calibrated unit still has, each off unless a scenario
  // turns it on (today's runs stay as they were). Magnitudes are 1 sigma per
  // axis, drawn once per run from the noise seed, each from its own stream.
  // Sources: MTi User Manual, MTi 10-series and 100-series, document MT0605P
  // (2018.E/2019.A), §4 sensor specifications and §5.2.1; Xsens base article
  // 203307252 "Bias repeatability of gyroscopes".
  // Scale factor: MT0605P gives no residual gain error after the factory
  // calibration, only the non-linearity (gyro 0.03 % FS, accelerometer 0.1 % FS),
  // which is used as the gain error's sigma.
  bool scale_factor_error = false;
  double gyro_scale_factor_sigma_pct = 0.03;
  double accel_scale_factor_sigma_pct = 0.1;
  // Non-orthogonality of the sensing axes: MT0605P §5.2.1, "< 0.05 deg".
  // Each triad (gyro, accelerometer) gets its own small off-diagonal terms.
  bool misalignment = false;
  double misalignment_sigma_deg = 0.05;
  // Gyro rate error per g of specific force, MT0605P gyroscope table:
  // g-sensitivity (calibrated) 0.006 deg/s/g for the 10-series (the MTi-300's
  // vibration-rejecting gyros: 0.003). A 3x3 matrix, every entry this sigma.
  bool g_sensitivity = false;
  double gyro_g_sensitivity_deg_s_per_g = 0.006;
  // The bias moving as the unit warms up over a run: an exponential approach
  // to a drawn offset. Size: the bias repeatability (the turn-on sigmas above,
  // 0.2 deg/s and 0.02 m/s2), which Xsens attributes partly to the warm-up;
  // time constant: the "at least 5 minutes" warm-up of the same article.
  bool temperature_drift = false;
  double gyro_temperature_drift_deg_s = 0.2;
  double accel_temperature_drift_m_s2 = 0.02;
  double warm_up_time_constant_s = 300.0;
  // Where the sample is really taken against its SampleTimeFine: uniform in
  // +-half a tick of the 10 kHz clock (docs/sensors.md), the resolution of the stamp.
  bool timestamp_jitter = false;
  double timestamp_jitter_s = 50e-6;
  // Vibration of the carrier beyond its modelled motion: a cage's bars
  // drumming on the floor, its frame ringing after an impact. An
  // oscillation (CarrierVibration, below: a frame's modes at 20-500 Hz,
  // excited by the bars' strikes at 10-15 Hz) of 1 sigma per axis
  // per_speed * |v| + per_accel * |a|, v and a of the body at that instant
  // (rolling speed, impacts). It is added to the specific force and rate the
  // unit senses at every 10 kHz sub-sample (then scale factor,
  // misalignment, g-sensitivity and clipping act on it as on the motion),
  // so the period's mean passes on what the device's strapdown integration
  // does: an oscillation's net velocity and angle over the period, which
  // consecutive samples take back (1 g at 30 Hz is a velocity of +-5 cm/s,
  // not a random walk). Below 100 Hz output the mean is taken from 100
  // sub-samples only (imu_model.cpp), which alias the higher modes: it is
  // meant for the device's 100-400 Hz. The shaking is the carrier's, not the
  // unit's: MT0605P specifies how the MTi-30 responds to vibration (its
  // g-sensitivity above, and the vibration-rejecting gyros of the 100-series),
  // not how much a rolling cage shakes. The magnitudes are an assumption: 1 g
  // RMS at the bench's 3.3 m/s, and 5 % of an impact's peak ringing on.
  bool vibration = false;
  double vibration_accel_m_s2_per_m_s = 3.0;
  double vibration_accel_per_m_s2 = 0.05;           // m/s2 of vibration per m/s2 of the body's acceleration
  double vibration_gyro_deg_s_per_m_s = 1.0;
  double vibration_gyro_deg_s_per_m_s2 = 0.02;
};

// The unit errors drawn for one run (identity / zero where a source is off).
struct ImuUnitErrors {
  Eigen::Matrix3d gyro_sensing = Eigen::Matrix3d::Identity();   // reading = this * true rate
  Eigen::Matrix3d accel_sensing = Eigen::Matrix3d::Identity();  // reading = this * true specific force
  Eigen::Matrix3d gyro_g_sensitivity_rad_s_per_m_s2 = Eigen::Matrix3d::Zero();
  Eigen::Vector3d gyro_warm_up_drift_rad_s = Eigen::Vector3d::Zero();  // reached after a long warm-up
  Eigen::Vector3d accel_warm_up_drift_m_s2 = Eigen::Vector3d::Zero();
};
ImuUnitErrors draw_imu_unit_errors(const ImuConfig& config, std::uint64_t seed);

// The device clock of one run.
struct ImuClock {
  double drift_ppm = 0.0;                 // device seconds run (1 + ppm 1e-6) times host seconds
  double first_sample_s = 0.0;            // run time of the first sample
  std::uint32_t first_sample_time_fine = 0;  // its SampleTimeFine (10 kHz ticks since power-up)
  std::uint16_t first_packet_counter = 0;
  // The rig's lidar-IMU time offset, in tumbled's convention: the sample sent
  // (and so stamped) at run time t measures the motion around t + this (the
  // mean over its period, centred there), so
  // tumbled's `imu.imu_time_offset_s` set to the same value cancels it.
  double imu_time_offset_s = 0.0;
};

// StatusWord clip bits (docs/sensors.md).
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
  double t_s = 0.0;  // run time the sample is sent for (it measures the period centred on t_s + imu_time_offset_s)
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();  // as reported (clipped at the range)
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  std::uint32_t status_word = 0;
  std::uint32_t sample_time_fine = 0;
  std::uint16_t packet_counter = 0;
};

// The carrier's vibration (ImuConfig::vibration): per axis, a sum of
// kVibrationModes sinusoids of unit RMS, drawn once per run.
inline constexpr int kVibrationModes = 8;
inline constexpr double kVibrationLowest_hz = 20.0, kVibrationHighest_hz = 500.0;
struct VibrationAxis {
  std::array<double, kVibrationModes> omega_rad_s{};
  std::array<double, kVibrationModes> phase_rad{};
  double at(double t_s) const;  // unit RMS
};
struct CarrierVibration {
  std::array<VibrationAxis, 3> accel, gyro;
};
// Frequencies log-uniform in [kVibrationLowest_hz, kVibrationHighest_hz],
// phases uniform; from its own stream, so it moves no other source's draws.
CarrierVibration draw_carrier_vibration(std::uint64_t seed);

class ImuModel {
 public:
  // noise_enabled = false gives the ideal readings (bias, noise and bias walk
  // off), still clipped at the range like the device; the error sources of
  // ImuConfig apply either way when they are on.
  ImuModel(const ImuConfig& config, const ImuClock& clock, const Eigen::Isometry3d& T_LI, const Motion& motion,
           std::uint64_t noise_seed, bool noise_enabled);

  // The k-th sample; false once past duration_s.
  bool next(double duration_s, ImuMeasurement& out);

  const Eigen::Vector3d& initial_gyro_bias_rad_s() const { return initial_gyro_bias_; }
  const Eigen::Vector3d& initial_accel_bias_m_s2() const { return initial_accel_bias_; }
  const ImuUnitErrors& unit_errors() const { return errors_; }

 private:
  Eigen::Vector3d gaussian3(double sigma);
  // The carrier's vibration (ImuConfig::vibration, on) at t_s, the body then
  // in `body`.
  ImuKinematics vibration_at(double t_s, const MotionState& body) const;
  struct ImuReadings {
    Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
    Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
    std::uint32_t status_word = 0;  // clip bits of the sub-samples
  };
  // The sensed readings (vibration, unit errors, clipping) averaged over the
  // 10 kHz sub-samples of the period centred on t_centre_s.
  ImuReadings readings_over_interval(double t_centre_s, double period_s) const;

  ImuConfig config_;
  ImuClock clock_;
  Eigen::Isometry3d T_LI_;
  const Motion& motion_;
  SensorRng rng_;
  SensorRng jitter_rng_;
  CarrierVibration vibration_;
  ImuUnitErrors errors_;
  bool noise_enabled_;
  std::uint64_t index_ = 0;
  Eigen::Vector3d gyro_bias_, accel_bias_;
  Eigen::Vector3d initial_gyro_bias_, initial_accel_bias_;
};

// Sample k's run time under the device clock: samples are evenly spaced in
// device time, so host-time spacing is period / (1 + drift).
double imu_sample_time_s(const ImuClock& clock, int rate_hz, std::uint64_t k);

}  // namespace tumble::sim
