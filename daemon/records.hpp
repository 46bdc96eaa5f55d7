// Plain-data items that travel between the daemon's threads. Fixed size and
// allocation-free to copy, so rings of them never touch the heap.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/point_weights.hpp"
#include "core/types.hpp"
#include "drivers/rs16/decoded_packet.hpp"

namespace tumble::daemon {

// The points of one lidar datagram, decoded on the io thread, with the block
// azimuths the registration thread's scan assembly splits on.
using PointBlock = rs16::DecodedPacket;

// One decoded IMU sample and when the io thread received the bytes that
// completed it (steady clock), for the arrival -> TUMBLE_ODOM latency.
struct ImuArrival {
  ImuSample sample;
  std::int64_t arrival_steady_ns = 0;
};

// One fused trajectory sample at IMU rate: the lidar pose T_WL(t) and its motion.
// Trivially copyable, as the seqlock trajectory buffer requires.
struct TrajectoryRecord {
  double t_s = 0.0;
  std::array<double, 4> q_wl_wxyz{1.0, 0.0, 0.0, 0.0};  // rotation W <- L
  std::array<double, 3> p_w_m{};
  std::array<double, 3> v_w_m_s{};
  std::array<double, 3> omega_l_rad_s{};  // in the lidar frame
  std::array<double, 3> position_var_m2{};
  std::array<double, 3> velocity_var_m2_s2{};
  std::uint8_t gyro_saturated_axes = 0;  // bit k = axis k clipped
  std::uint8_t accel_saturated_axes = 0;
  bool lidar_corrected = false;       // the velocity already includes a registered scan
  bool attitude_from_device = false;  // orientation is the IMU's own estimate, not Madgwick's
  std::int64_t imu_arrival_steady_ns = 0;  // ImuArrival::arrival_steady_ns of the sample; 0: unknown
};

using tumble::WeightModel;

// One registered scan, as the registration thread reports it (to the fuser as
// a correction, to LCM as tumble.registration_t, to the trajectory file).
struct RegistrationRecord {
  static constexpr std::size_t kMaxStages = 8;
  double t_s = 0.0;  // the scan's first point
  std::int64_t scan_index = 0;
  std::array<double, 3> position_m{};
  std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};
  std::array<double, 3> velocity_m_s{};
  std::array<double, 36> covariance{};  // 6x6 row-major over (tx, ty, tz, rx, ry, rz)
  std::int32_t iterations = 0;
  bool registered = false;       // false: the fuser's pose is reported and no correction is made
  bool map_initialised = false;  // the scan that started the map
  bool converged = false;
  double position_sigma_m = 0.0;  // for the fuser's velocity filter
  float inlier_ratio = 0.0f;
  float residual_m = 0.0f;
  float degeneracy = 0.0f;
  WeightModel model = WeightModel::GVTW;
  bool deskew = true;
  std::int32_t points_in = 0;
  std::int32_t points_used = 0;
  float sigma_s_median_m = 0.0f;
  float sigma_s_max_m = 0.0f;
  std::int64_t scan_complete_steady_ns = 0;  // when the scan's last packet was taken (for latency)
  std::uint8_t num_stages = 0;               // names: RegistrationStage::stage_names()
  std::array<float, kMaxStages> stage_ms{};
};

}  // namespace tumble::daemon
