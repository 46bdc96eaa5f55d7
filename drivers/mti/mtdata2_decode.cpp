#include "drivers/mti/mtdata2_decode.hpp"

#include "drivers/mti/big_endian.hpp"
#include "drivers/mti/mtdata2_packets.hpp"
#include "drivers/mti/xdi.hpp"

namespace tumble::mti {
namespace {

template <std::size_t N>
std::array<double, N> reals(const MtData2Packet& p) {
  const NumberFormat f = number_format_of(p.xdi);
  const std::size_t step = number_format_bytes(f);
  std::array<double, N> v{};
  for (std::size_t i = 0; i < N; ++i) v[i] = read_real(p.data.data() + i * step, f);
  return v;
}

Eigen::Vector3d vector3(const MtData2Packet& p) {
  const auto v = reals<3>(p);
  return {v[0], v[1], v[2]};
}

UtcTime utc_time(const std::uint8_t* d) {
  UtcTime t;
  t.nanosecond = read_u32_be(d);
  t.year = read_u16_be(d + 4);
  t.month = d[6];
  t.day = d[7];
  t.hour = d[8];
  t.minute = d[9];
  t.second = d[10];
  t.flags = d[11];
  return t;
}

std::int32_t i32(const std::uint8_t* d) { return static_cast<std::int32_t>(read_u32_be(d)); }

GnssPvt gnss_pvt(const std::uint8_t* d) {
  GnssPvt g;
  g.itow_ms = read_u32_be(d);
  g.year = read_u16_be(d + 4);
  g.month = d[6];
  g.day = d[7];
  g.hour = d[8];
  g.minute = d[9];
  g.second = d[10];
  g.valid = d[11];
  g.time_accuracy_ns = read_u32_be(d + 12);
  g.nano_ns = i32(d + 16);
  g.fix_type = d[20];
  g.flags = d[21];
  g.satellites = d[22];
  g.reserved1 = d[23];
  g.lon_1e7_deg = i32(d + 24);
  g.lat_1e7_deg = i32(d + 28);
  g.height_mm = i32(d + 32);
  g.height_msl_mm = i32(d + 36);
  g.horizontal_accuracy_mm = read_u32_be(d + 40);
  g.vertical_accuracy_mm = read_u32_be(d + 44);
  g.vel_n_mm_s = i32(d + 48);
  g.vel_e_mm_s = i32(d + 52);
  g.vel_d_mm_s = i32(d + 56);
  g.ground_speed_mm_s = i32(d + 60);
  g.heading_motion_1e5_deg = i32(d + 64);
  g.speed_accuracy_mm_s = read_u32_be(d + 68);
  g.heading_accuracy_1e5_deg = read_u32_be(d + 72);
  g.heading_vehicle_1e5_deg = i32(d + 76);
  g.gdop = read_u16_be(d + 80);
  g.pdop = read_u16_be(d + 82);
  g.tdop = read_u16_be(d + 84);
  g.vdop = read_u16_be(d + 86);
  g.hdop = read_u16_be(d + 88);
  g.ndop = read_u16_be(d + 90);
  g.edop = read_u16_be(d + 92);
  return g;
}

void store(const MtData2Packet& p, MtData2& m) {
  const std::uint8_t* d = p.data.data();
  switch (p.xdi & xdi::kTypeMask) {
    case xdi::kTemperature: m.temperature_c = reals<1>(p)[0]; break;
    case xdi::kUtcTime: m.utc_time = utc_time(d); break;
    case xdi::kPacketCounter: m.packet_counter = read_u16_be(d); break;
    case xdi::kSampleTimeFine: m.sample_time_fine = read_u32_be(d); break;
    case xdi::kSampleTimeCoarse: m.sample_time_coarse = read_u32_be(d); break;
    case xdi::kQuaternion:
      m.quaternion = reals<4>(p);
      m.orientation_xdi = p.xdi;
      break;
    case xdi::kRotationMatrix:
      m.rotation_matrix = reals<9>(p);
      m.orientation_xdi = p.xdi;
      break;
    case xdi::kEulerAngles:
      m.euler_angles_deg = vector3(p);
      m.orientation_xdi = p.xdi;
      break;
    case xdi::kBaroPressure: m.baro_pressure_pa = read_u32_be(d); break;
    case xdi::kDeltaV: m.delta_v_m_s = vector3(p); break;
    case xdi::kAcceleration: m.acceleration_m_s2 = vector3(p); break;
    case xdi::kFreeAcceleration: m.free_acceleration_m_s2 = vector3(p); break;
    case xdi::kAltitudeEllipsoid: m.altitude_ellipsoid_m = reals<1>(p)[0]; break;
    case xdi::kPositionEcef: m.position_ecef_m = vector3(p); break;
    case xdi::kLatLon: m.lat_lon_deg = reals<2>(p); break;
    case xdi::kGnssPvtData: m.gnss_pvt = gnss_pvt(d); break;
    case xdi::kGnssSatInfo: {
      GnssSatInfo s;
      s.itow_ms = read_u32_be(d);
      s.satellites = d[4];
      s.reserved = {d[5], d[6], d[7]};
      m.gnss_sat_info = s;
      break;
    }
    case xdi::kRateOfTurn: m.rate_of_turn_rad_s = vector3(p); break;
    case xdi::kDeltaQ: m.delta_q = reals<4>(p); break;
    case xdi::kMagneticField: m.magnetic_field_au = vector3(p); break;
    case xdi::kVelocityXyz: m.velocity_m_s = vector3(p); break;
    case xdi::kStatusByte: m.status_byte = d[0]; break;
    case xdi::kStatusWord: m.status_word = read_u32_be(d); break;
    default: break;
  }
}

}  // namespace

bool decode_mtdata2(std::span<const std::uint8_t> payload, MtData2& msg, MtData2DecodeStats& stats) {
  msg = MtData2{};
  MtData2PacketReader reader(payload);
  std::uint64_t mismatches = 0;
  std::uint64_t unknown = 0;
  while (const auto packet = reader.next()) {
    const xdi::Info* info = xdi::find(packet->xdi);
    if (info == nullptr) {
      ++unknown;
    } else if (!xdi::size_fits(*info, packet->xdi, packet->data.size())) {
      ++mismatches;
    } else {
      store(*packet, msg);
    }
  }
  stats.size_mismatches += mismatches;
  stats.unknown_packets += unknown;
  if (reader.truncated()) {
    ++stats.truncated_messages;
    msg = MtData2{};
    return false;
  }
  ++stats.messages;
  return true;
}

}  // namespace tumble::mti
