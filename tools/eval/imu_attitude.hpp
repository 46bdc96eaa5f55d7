// `tumble-eval imu`: the fuser alone (core/imu_fuser, no lidar) on an IMU
// recording (our pcap or a raw Xsens byte stream, read as tumbled reads it),
// judged where the truth is known without a reference system: while the IMU
// stands still its accelerometer measures gravity, so the attitude's tilt
// (roll, pitch; not yaw) can be checked against it. The device's own
// quaternion, where the recording has one, is compared too: as another
// estimate, not as the truth.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace tumble::eval {

struct ImuEvalOptions {
  double fuser_static_s = 0.5;     // the fuser's initial still window (tumbled: core.imu static_duration_s)
  double still_min_s = 0.5;        // shorter still stretches are not reported as still periods
  double still_gyro_rad_s = 0.05;  // ‖ω‖ below this ...
  double still_accel_m_s2 = 0.2;   // ... and |‖a‖ − g| below this: the sample is still
};

// One sample after the fuser initialised. "Up" is the world's z axis seen in
// the IMU frame: what a still accelerometer measures, normalised.
struct AttitudeSample {
  double t_s = 0.0;
  Eigen::Quaterniond q_wi = Eigen::Quaterniond::Identity();  // ours
  Eigen::Vector3d up_ours = Eigen::Vector3d::UnitZ();
  std::optional<Eigen::Vector3d> up_device;  // from the device's own orientation output (quaternion or Euler angles)
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
  bool still = false;
};

struct StillPeriod {
  double begin_s = 0.0, end_s = 0.0;
  std::size_t samples = 0;
  Eigen::Vector3d mean_gyro_rad_s = Eigen::Vector3d::Zero();  // the gyro bias there
  // Ours against the accelerometer at the period's first sample (after the
  // fuser initialised): the tilt error the motion before it left, before
  // the accelerometer corrects it.
  std::optional<double> entry_tilt_deg;
};

struct AngleStats {
  std::size_t count = 0;
  double median_deg = 0.0, p95_deg = 0.0, max_deg = 0.0;
};

struct ImuEvaluation {
  std::string recording;
  std::string format;             // "pcap" or "raw bytes"
  std::string reader_problem;     // what the reader found wrong, empty when clean
  std::size_t samples = 0;        // IMU samples decoded
  double duration_s = 0.0;
  std::optional<double> initialized_at_s;  // when the fuser's still window completed
  Eigen::Vector3d fuser_gyro_bias_rad_s = Eigen::Vector3d::Zero();
  std::vector<StillPeriod> still_periods;
  std::vector<AttitudeSample> attitude;  // from the fuser's initialisation on
  std::optional<AngleStats> ours_vs_accel;     // tilt error on still samples
  std::optional<AngleStats> device_vs_accel;
  std::optional<AngleStats> ours_vs_device;    // tilt difference, every sample
  std::array<std::uint64_t, 3> gyro_clipped{};   // samples per axis
  std::array<std::uint64_t, 3> accel_clipped{};
  std::uint64_t samples_clipped = 0;           // any axis
};

// Throws std::runtime_error naming the file when it cannot be read.
ImuEvaluation evaluate_imu_recording(const std::filesystem::path& recording, const ImuEvalOptions& options);

// roll = atan2(u_y, u_z), pitch = atan2(−u_x, √(u_y² + u_z²)) of an up vector (rad).
Eigen::Vector2d roll_pitch_rad(const Eigen::Vector3d& up);
double tilt_between_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

std::string imu_report_markdown(const ImuEvaluation& evaluation);
// "t 0 0 0 qx qy qz qw" per sample (the IMU's attitude in the fuser's W).
void write_attitude_tum(const ImuEvaluation& evaluation, const std::filesystem::path& path);
// Roll and pitch over time, ours beside the device's, as PNG via gnuplot (the
// script is kept beside it). Returns "" or why the plot could not be drawn.
std::string draw_roll_pitch(const ImuEvaluation& evaluation, const std::filesystem::path& script_path,
                            const std::filesystem::path& png_path);

}  // namespace tumble::eval
