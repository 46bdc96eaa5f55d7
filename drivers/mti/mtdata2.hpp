// One decoded MTData2 message: every output this driver knows, each present
// only when the message carried it. Plain data; real values in SI or the
// device's units as noted, whatever number format they came in.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>

namespace tumble::mti {

struct UtcTime {
  std::uint32_t nanosecond = 0;
  std::uint16_t year = 0;
  std::uint8_t month = 0, day = 0, hour = 0, minute = 0, second = 0;
  std::uint8_t flags = 0;  // validity bits
};

// u-blox NAV-PVT as the MTi forwards it (GnssPvtData, 94 bytes).
struct GnssPvt {
  std::uint32_t itow_ms = 0;
  std::uint16_t year = 0;
  std::uint8_t month = 0, day = 0, hour = 0, minute = 0, second = 0, valid = 0;
  std::uint32_t time_accuracy_ns = 0;
  std::int32_t nano_ns = 0;
  std::uint8_t fix_type = 0, flags = 0, satellites = 0, reserved1 = 0;
  std::int32_t lon_1e7_deg = 0, lat_1e7_deg = 0, height_mm = 0, height_msl_mm = 0;
  std::uint32_t horizontal_accuracy_mm = 0, vertical_accuracy_mm = 0;
  std::int32_t vel_n_mm_s = 0, vel_e_mm_s = 0, vel_d_mm_s = 0, ground_speed_mm_s = 0;
  std::int32_t heading_motion_1e5_deg = 0;
  std::uint32_t speed_accuracy_mm_s = 0, heading_accuracy_1e5_deg = 0;
  std::int32_t heading_vehicle_1e5_deg = 0;
  std::uint16_t gdop = 0, pdop = 0, tdop = 0, vdop = 0, hdop = 0, ndop = 0, edop = 0;  // 0.01 units
};

// GnssSatInfo header; the per-satellite records are not kept.
struct GnssSatInfo {
  std::uint32_t itow_ms = 0;
  std::uint8_t satellites = 0;
  std::array<std::uint8_t, 3> reserved{};
};

struct MtData2 {
  std::optional<std::uint16_t> packet_counter;
  std::optional<std::uint32_t> sample_time_fine;    // 10 kHz ticks, wraps at 864'000'000
  std::optional<std::uint32_t> sample_time_coarse;  // s
  std::optional<UtcTime> utc_time;
  std::optional<std::uint32_t> status_word;
  std::optional<std::uint8_t> status_byte;
  std::optional<std::array<double, 4>> quaternion;        // w x y z
  std::optional<std::array<double, 9>> rotation_matrix;   // as sent: column-major
  std::optional<Eigen::Vector3d> euler_angles_deg;        // roll pitch yaw
  std::optional<Eigen::Vector3d> delta_v_m_s;
  std::optional<Eigen::Vector3d> acceleration_m_s2;
  std::optional<Eigen::Vector3d> free_acceleration_m_s2;
  std::optional<Eigen::Vector3d> rate_of_turn_rad_s;
  std::optional<std::array<double, 4>> delta_q;           // w x y z
  std::optional<Eigen::Vector3d> magnetic_field_au;
  std::optional<Eigen::Vector3d> velocity_m_s;
  std::optional<Eigen::Vector3d> position_ecef_m;
  std::optional<std::array<double, 2>> lat_lon_deg;
  std::optional<double> altitude_ellipsoid_m;
  std::optional<double> temperature_c;
  std::optional<std::uint32_t> baro_pressure_pa;
  std::optional<GnssPvt> gnss_pvt;
  std::optional<GnssSatInfo> gnss_sat_info;
  // XDI of the orientation outputs as sent (coordinate system and format).
  std::uint16_t orientation_xdi = 0;
};

}  // namespace tumble::mti
