#include "tools/eval/imu_attitude.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/angles.hpp"
#include "core/imu_fuser.hpp"
#include "core/types.hpp"
#include "drivers/mti/imu_recording_reader.hpp"

namespace tumble::eval {
namespace {

// Coordinate-system bits of an orientation XDI (docs/sensors.md): 01 = NED, whose up is −z.
constexpr std::uint16_t kCoordinateMask = 0x000C;
constexpr std::uint16_t kCoordinateNed = 0x0004;

std::optional<AngleStats> angle_stats(std::vector<double> deg) {
  if (deg.empty()) return std::nullopt;
  std::sort(deg.begin(), deg.end());
  const auto at = [&deg](double p) { return deg[static_cast<std::size_t>(std::lround(p * (deg.size() - 1)))]; };
  return AngleStats{deg.size(), at(0.5), at(0.95), deg.back()};
}

bool looks_still(const ImuSample& s, const ImuEvalOptions& o) {
  return s.gyro_rad_s.norm() < o.still_gyro_rad_s && std::abs(s.accel_m_s2.norm() - kStandardGravity_m_s2) < o.still_accel_m_s2;
}

// Runs of still samples at least still_min_s long.
std::vector<StillPeriod> find_still_periods(const std::vector<ImuSample>& samples, const ImuEvalOptions& o) {
  std::vector<StillPeriod> periods;
  std::size_t i = 0;
  while (i < samples.size()) {
    if (!looks_still(samples[i], o)) {
      ++i;
      continue;
    }
    std::size_t j = i;
    Eigen::Vector3d gyro_sum = Eigen::Vector3d::Zero();
    while (j < samples.size() && looks_still(samples[j], o)) gyro_sum += samples[j++].gyro_rad_s;
    const double length_s = samples[j - 1].t_s - samples[i].t_s;
    if (length_s >= o.still_min_s)
      periods.push_back({samples[i].t_s, samples[j - 1].t_s, j - i, gyro_sum / static_cast<double>(j - i), std::nullopt});
    i = j;
  }
  return periods;
}

// The world's up in the sensor frame from the device's own orientation output
// (quaternion or Euler angles, both sensor -> world); nullopt without one.
std::optional<Eigen::Vector3d> device_up_in_sensor(const mti::MtData2& m) {
  const Eigen::Vector3d world_up(0.0, 0.0, (m.orientation_xdi & kCoordinateMask) == kCoordinateNed ? -1.0 : 1.0);
  if (m.quaternion) {
    const auto& q = *m.quaternion;
    return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().conjugate() * world_up;
  }
  if (m.euler_angles_deg) {
    const Eigen::Vector3d rpy = *m.euler_angles_deg * (std::numbers::pi / 180.0);
    const Eigen::Matrix3d R_ws = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                                     .toRotationMatrix();
    return R_ws.transpose() * world_up;
  }
  return std::nullopt;
}

}  // namespace

Eigen::Vector2d roll_pitch_rad(const Eigen::Vector3d& up) {
  return {std::atan2(up.y(), up.z()), std::atan2(-up.x(), std::hypot(up.y(), up.z()))};
}

double tilt_between_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * kRadToDeg;
}

ImuEvaluation evaluate_imu_recording(const std::filesystem::path& recording, const ImuEvalOptions& options) {
  ImuEvaluation e;
  e.recording = recording.string();
  mti::ImuRecordingReader reader(recording.string(), mti::MtiStreamOptions{});
  e.format = reader.format() == mti::RecordingFormat::Pcap ? "pcap" : "raw bytes";
  std::vector<ImuSample> samples;
  std::vector<std::optional<Eigen::Vector3d>> device_up;  // per sample
  reader.set_sample_observer([&device_up](const ImuSample&, const mti::MtData2& m, std::optional<std::int64_t>) {
    device_up.push_back(device_up_in_sensor(m));
  });
  while (reader.next(samples)) {
  }
  e.reader_problem = reader.problem();
  e.samples = samples.size();
  if (samples.empty()) return e;
  e.duration_s = samples.back().t_s - samples.front().t_s;

  for (const ImuSample& s : samples) {
    bool any = false;
    for (int k = 0; k < 3; ++k) {
      e.gyro_clipped[k] += s.gyro_saturated[k];
      e.accel_clipped[k] += s.accel_saturated[k];
      any = any || s.gyro_saturated[k] || s.accel_saturated[k];
    }
    e.samples_clipped += any;
  }
  e.still_periods = find_still_periods(samples, options);

  ImuFuserParams params;
  params.static_duration_s = options.fuser_static_s;
  params.static_max_gyro_rad_s = options.still_gyro_rad_s;
  ImuFuser fuser(params);
  std::vector<double> ours_vs_accel, device_vs_accel, ours_vs_device;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const ImuSample& s = samples[i];
    fuser.add_imu(s);
    if (!fuser.initialized() || fuser.trajectory().empty() || fuser.trajectory().back().t_s != s.t_s) continue;
    if (!e.initialized_at_s) {
      e.initialized_at_s = s.t_s;
      e.fuser_gyro_bias_rad_s = fuser.gyro_bias_rad_s();
    }
    AttitudeSample a;
    a.t_s = s.t_s;
    a.q_wi = fuser.trajectory().back().q_wl;  // T_LI is the identity here: the lidar frame is the IMU's
    a.up_ours = a.q_wi.conjugate() * Eigen::Vector3d::UnitZ();
    if (i < device_up.size()) a.up_device = device_up[i];
    a.accel_m_s2 = s.accel_m_s2;
    const auto period = std::find_if(e.still_periods.begin(), e.still_periods.end(),
                                     [&s](const StillPeriod& p) { return s.t_s >= p.begin_s && s.t_s <= p.end_s; });
    a.still = period != e.still_periods.end();
    if (a.still) {
      ours_vs_accel.push_back(tilt_between_deg(a.up_ours, a.accel_m_s2));
      if (!period->entry_tilt_deg) period->entry_tilt_deg = ours_vs_accel.back();
      if (a.up_device) device_vs_accel.push_back(tilt_between_deg(*a.up_device, a.accel_m_s2));
    }
    if (a.up_device) ours_vs_device.push_back(tilt_between_deg(a.up_ours, *a.up_device));
    e.attitude.push_back(a);
  }
  e.ours_vs_accel = angle_stats(std::move(ours_vs_accel));
  e.device_vs_accel = angle_stats(std::move(device_vs_accel));
  e.ours_vs_device = angle_stats(std::move(ours_vs_device));
  return e;
}

}  // namespace tumble::eval
