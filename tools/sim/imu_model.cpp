#include "tools/sim/imu_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/angles.hpp"

namespace tumble::sim {
namespace {

constexpr double kMicroG = kStandardGravity_m_s2 * 1e-6;
constexpr std::uint32_t kTicksPerSecond = 10'000;
constexpr int kSensorSampleRate_hz = 10'000;  // the unit samples its sensors at this rate
// Below 100 Hz (tests of slow effects at 1 Hz) the period's mean is taken
// from this many evenly spaced sub-samples instead: 10 kHz over a 600 s
// warm-up took two minutes of a test.
constexpr int kMaxSubSamples = 100;
constexpr std::uint64_t kSampleTimeFineWrap = 864'000'000;  // one day of ticks
constexpr double kBiasStabilityHorizonS = 100.0;

// Clips each axis at +-range like the device: the value becomes the limit and
// the axis's bit (first_bit + axis) is set.
std::uint32_t clip(Eigen::Vector3d& v, double range, std::uint32_t first_bit) {
  std::uint32_t status = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(v[axis]) > range) {
      v[axis] = std::copysign(range, v[axis]);
      status |= first_bit << axis;
    }
  }
  return status;
}

Eigen::Vector3d normal3(SensorRng& rng, double sigma) {
  const double x = rng.normal(sigma), y = rng.normal(sigma), z = rng.normal(sigma);
  return {x, y, z};
}

// Small-angle non-orthogonality: each sensing axis leans towards the other two.
Eigen::Matrix3d misaligned(SensorRng& rng, double sigma_rad) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (r != c) m(r, c) = rng.normal(sigma_rad);
  return m;
}

}  // namespace

ImuUnitErrors draw_imu_unit_errors(const ImuConfig& c, std::uint64_t seed) {
  // One stream per source: turning one on never moves another's draws.
  ImuUnitErrors e;
  if (c.misalignment) {
    SensorRng rng(seed, "imu-misalignment");
    e.gyro_sensing = misaligned(rng, c.misalignment_sigma_deg * kDegToRad);
    e.accel_sensing = misaligned(rng, c.misalignment_sigma_deg * kDegToRad);
  }
  if (c.scale_factor_error) {
    SensorRng rng(seed, "imu-scale-factor");
    const Eigen::Vector3d gyro_gain = Eigen::Vector3d::Ones() + normal3(rng, c.gyro_scale_factor_sigma_pct * 1e-2);
    const Eigen::Vector3d accel_gain = Eigen::Vector3d::Ones() + normal3(rng, c.accel_scale_factor_sigma_pct * 1e-2);
    e.gyro_sensing = gyro_gain.asDiagonal() * e.gyro_sensing;
    e.accel_sensing = accel_gain.asDiagonal() * e.accel_sensing;
  }
  if (c.g_sensitivity) {
    SensorRng rng(seed, "imu-g-sensitivity");
    const double sigma = c.gyro_g_sensitivity_deg_s_per_g * kDegToRad / kStandardGravity_m_s2;
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) e.gyro_g_sensitivity_rad_s_per_m_s2(r, col) = rng.normal(sigma);
  }
  if (c.temperature_drift) {
    SensorRng rng(seed, "imu-temperature-drift");
    e.gyro_warm_up_drift_rad_s = normal3(rng, c.gyro_temperature_drift_deg_s * kDegToRad);
    e.accel_warm_up_drift_m_s2 = normal3(rng, c.accel_temperature_drift_m_s2);
  }
  return e;
}

ImuKinematics imu_kinematics(const MotionState& body, const Eigen::Isometry3d& T_LI) {
  const Eigen::Vector3d& r = T_LI.translation();
  const Eigen::Vector3d& w = body.omega_b;
  const Eigen::Vector3d gravity_w(0.0, 0.0, -kStandardGravity_m_s2);
  const Eigen::Vector3d f_body =
      body.T_wb.linear().transpose() * (body.a_w - gravity_w) + body.alpha_b.cross(r) + w.cross(w.cross(r));
  const Eigen::Matrix3d R_il = T_LI.linear().transpose();
  return ImuKinematics{R_il * f_body, R_il * w};
}

double imu_sample_time_s(const ImuClock& clock, int rate_hz, std::uint64_t k) {
  return clock.first_sample_s + static_cast<double>(k) / rate_hz / (1.0 + clock.drift_ppm * 1e-6);
}

ImuModel::ImuModel(const ImuConfig& config, const ImuClock& clock, const Eigen::Isometry3d& T_LI,
                   const Motion& motion, std::uint64_t noise_seed, bool noise_enabled)
    : config_(config), clock_(clock), T_LI_(T_LI), motion_(motion), rng_(noise_seed, "imu"),
      jitter_rng_(noise_seed, "imu-timestamp-jitter"), vibration_(draw_carrier_vibration(noise_seed)),
      errors_(draw_imu_unit_errors(config, noise_seed)), noise_enabled_(noise_enabled) {
  gyro_bias_ = noise_enabled_ ? gaussian3(config_.gyro_initial_bias_sigma_deg_s * kDegToRad) : Eigen::Vector3d::Zero();
  accel_bias_ = noise_enabled_ ? gaussian3(config_.accel_initial_bias_sigma_m_s2) : Eigen::Vector3d::Zero();
  initial_gyro_bias_ = gyro_bias_;
  initial_accel_bias_ = accel_bias_;
}

Eigen::Vector3d ImuModel::gaussian3(double sigma) {
  const double x = rng_.normal(sigma), y = rng_.normal(sigma), z = rng_.normal(sigma);
  return {x, y, z};
}

CarrierVibration draw_carrier_vibration(std::uint64_t seed) {
  SensorRng rng(seed, "imu-vibration");
  const auto draw_axis = [&rng] {
    VibrationAxis axis;
    for (int m = 0; m < kVibrationModes; ++m) {
      const double f_hz = kVibrationLowest_hz * std::pow(kVibrationHighest_hz / kVibrationLowest_hz, rng.uniform());
      axis.omega_rad_s[m] = 2.0 * std::numbers::pi * f_hz;
      axis.phase_rad[m] = rng.uniform(0.0, 2.0 * std::numbers::pi);
    }
    return axis;
  };
  CarrierVibration v;
  for (VibrationAxis& axis : v.accel) axis = draw_axis();
  for (VibrationAxis& axis : v.gyro) axis = draw_axis();
  return v;
}

double VibrationAxis::at(double t_s) const {
  // Each sinusoid's RMS is its amplitude / sqrt(2); the modes are independent.
  const double unit_rms_amplitude = std::sqrt(2.0 / kVibrationModes);
  double sum = 0.0;
  for (int m = 0; m < kVibrationModes; ++m) sum += std::sin(omega_rad_s[m] * t_s + phase_rad[m]);
  return unit_rms_amplitude * sum;
}

ImuKinematics ImuModel::vibration_at(double t_s, const MotionState& body) const {
  const double speed = body.v_w.norm(), accel = body.a_w.norm();
  const double accel_sigma_m_s2 =
      config_.vibration_accel_m_s2_per_m_s * speed + config_.vibration_accel_per_m_s2 * accel;
  const double gyro_sigma_rad_s =
      (config_.vibration_gyro_deg_s_per_m_s * speed + config_.vibration_gyro_deg_s_per_m_s2 * accel) * kDegToRad;
  ImuKinematics v;
  for (int axis = 0; axis < 3; ++axis) {
    v.specific_force_i[axis] = accel_sigma_m_s2 * vibration_.accel[axis].at(t_s);
    v.omega_i[axis] = gyro_sigma_rad_s * vibration_.gyro[axis].at(t_s);
  }
  return v;
}

ImuModel::ImuReadings ImuModel::readings_over_interval(double t_centre_s, double period_s) const {
  const int substeps = std::clamp(kSensorSampleRate_hz / config_.rate_hz, 1, kMaxSubSamples);
  ImuReadings out;
  for (int j = 0; j < substeps; ++j) {
    const double t = t_centre_s + period_s * ((j + 0.5) / substeps - 0.5);
    const MotionState body = motion_.at(t);
    ImuKinematics ideal = imu_kinematics(body, T_LI_);
    if (config_.vibration) {
      const ImuKinematics vibration = vibration_at(t, body);
      ideal.specific_force_i += vibration.specific_force_i;
      ideal.omega_i += vibration.omega_i;
    }
    Eigen::Vector3d gyro =
        errors_.gyro_sensing * ideal.omega_i + errors_.gyro_g_sensitivity_rad_s_per_m_s2 * ideal.specific_force_i;
    Eigen::Vector3d accel = errors_.accel_sensing * ideal.specific_force_i;
    out.status_word |= clip(accel, config_.accel_range_m_s2, kStatusAccelClipX);
    out.status_word |= clip(gyro, config_.gyro_range_deg_s * kDegToRad, kStatusGyroClipX);
    out.accel_m_s2 += accel;
    out.gyro_rad_s += gyro;
  }
  out.accel_m_s2 /= substeps;
  out.gyro_rad_s /= substeps;
  return out;
}

bool ImuModel::next(double duration_s, ImuMeasurement& out) {
  const double t_s = imu_sample_time_s(clock_, config_.rate_hz, index_);
  if (t_s > duration_s) return false;
  const double jitter_s =
      config_.timestamp_jitter ? jitter_rng_.uniform(-config_.timestamp_jitter_s, config_.timestamp_jitter_s) : 0.0;
  const double t_measured_s = t_s + clock_.imu_time_offset_s + jitter_s;
  const ImuReadings sensed = readings_over_interval(t_measured_s, 1.0 / config_.rate_hz);
  out.t_s = t_s;
  out.gyro_rad_s = sensed.gyro_rad_s;
  out.accel_m_s2 = sensed.accel_m_s2;
  if (config_.temperature_drift) {
    const double warmed = 1.0 - std::exp(-(t_s - clock_.first_sample_s) / config_.warm_up_time_constant_s);
    out.gyro_rad_s += warmed * errors_.gyro_warm_up_drift_rad_s;
    out.accel_m_s2 += warmed * errors_.accel_warm_up_drift_m_s2;
  }
  if (noise_enabled_) {
    // White noise of density N sampled at f has sigma N sqrt(f).
    const double sqrt_rate = std::sqrt(static_cast<double>(config_.rate_hz));
    out.gyro_rad_s += gyro_bias_ + gaussian3(config_.gyro_noise_density_deg_s_sqrt_hz * kDegToRad * sqrt_rate);
    out.accel_m_s2 += accel_bias_ + gaussian3(config_.accel_noise_density_ug_sqrt_hz * kMicroG * sqrt_rate);
    const double walk = std::sqrt(1.0 / config_.rate_hz / kBiasStabilityHorizonS);
    gyro_bias_ += gaussian3(config_.gyro_bias_stability_deg_h * kDegToRad / 3600.0 * walk);
    accel_bias_ += gaussian3(config_.accel_bias_stability_ug * kMicroG * walk);
  }
  std::uint32_t status = sensed.status_word;
  status |= clip(out.accel_m_s2, config_.accel_range_m_s2, kStatusAccelClipX);
  status |= clip(out.gyro_rad_s, config_.gyro_range_deg_s * kDegToRad, kStatusGyroClipX);
  if (status != 0) status |= kStatusAnyClip;
  out.status_word = status;
  const std::uint64_t ticks = clock_.first_sample_time_fine + index_ * (kTicksPerSecond / config_.rate_hz);
  out.sample_time_fine = static_cast<std::uint32_t>(ticks % kSampleTimeFineWrap);
  out.packet_counter = static_cast<std::uint16_t>(clock_.first_packet_counter + index_);
  ++index_;
  return true;
}

}  // namespace tumble::sim
