#include "drivers/mti/mtdata2_encode.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include "drivers/mti/big_endian.hpp"
#include "drivers/mti/xdi.hpp"

namespace tumble::mti {

void append_reals_packet(std::vector<std::uint8_t>& out, std::uint16_t type, std::span<const double> values,
                         NumberFormat fmt) {
  const std::size_t size = values.size() * number_format_bytes(fmt);
  if (size > 255) throw std::invalid_argument("MTData2 packet of " + std::to_string(size) + " bytes exceeds 255");
  append_u16_be(out, static_cast<std::uint16_t>((type & ~kNumberFormatMask) | static_cast<std::uint16_t>(fmt)));
  out.push_back(static_cast<std::uint8_t>(size));
  for (const double v : values) append_real(out, v, fmt);
}

void append_u16_packet(std::vector<std::uint8_t>& out, std::uint16_t xdi, std::uint16_t value) {
  append_u16_be(out, xdi);
  out.push_back(2);
  append_u16_be(out, value);
}

void append_u32_packet(std::vector<std::uint8_t>& out, std::uint16_t xdi, std::uint32_t value) {
  append_u16_be(out, xdi);
  out.push_back(4);
  append_u32_be(out, value);
}

void append_raw_packet(std::vector<std::uint8_t>& out, std::uint16_t xdi, std::span<const std::uint8_t> data) {
  if (data.size() > 255)
    throw std::invalid_argument("MTData2 packet of " + std::to_string(data.size()) + " bytes exceeds 255");
  append_u16_be(out, xdi);
  out.push_back(static_cast<std::uint8_t>(data.size()));
  out.insert(out.end(), data.begin(), data.end());
}

std::vector<std::uint8_t> encode_mtdata2(const MtData2Out& m, NumberFormat fmt) {
  std::vector<std::uint8_t> out;
  out.reserve(5 + 7 + 2 * (3 + 3 * 8) + 7);
  append_u16_packet(out, xdi::kPacketCounter, m.packet_counter);
  append_u32_packet(out, xdi::kSampleTimeFine, m.sample_time_fine);
  const std::array<double, 3> accel{m.accel_m_s2.x(), m.accel_m_s2.y(), m.accel_m_s2.z()};
  const std::array<double, 3> gyro{m.gyro_rad_s.x(), m.gyro_rad_s.y(), m.gyro_rad_s.z()};
  append_reals_packet(out, xdi::kAcceleration, accel, fmt);
  append_reals_packet(out, xdi::kRateOfTurn, gyro, fmt);
  append_u32_packet(out, xdi::kStatusWord, m.status_word);
  return out;
}

}  // namespace tumble::mti
