// Builds MTData2 payloads, as an MTi would send them (for the simulator and tests).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "drivers/mti/number_format.hpp"

namespace tumble::mti {

struct MtData2Out {
  std::uint16_t packet_counter = 0;
  std::uint32_t sample_time_fine = 0;  // 10 kHz ticks, wraps at 864'000'000
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();  // as the device reports it (already clipped)
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  std::uint32_t status_word = 0;  // clip bits 8..13 and 19 set by the caller
};

// MTData2 payload: PacketCounter, SampleTimeFine, Acceleration, RateOfTurn, StatusWord.
std::vector<std::uint8_t> encode_mtdata2(const MtData2Out& m, NumberFormat fmt = NumberFormat::Float32);

// Packet builders for other outputs. type = the XDI without format bits (it may
// carry coordinate bits); the format is or-ed in for real values.
void append_reals_packet(std::vector<std::uint8_t>& out, std::uint16_t type, std::span<const double> values,
                         NumberFormat fmt);
void append_u16_packet(std::vector<std::uint8_t>& out, std::uint16_t xdi, std::uint16_t value);
void append_u32_packet(std::vector<std::uint8_t>& out, std::uint16_t xdi, std::uint32_t value);
// Any bytes as one packet (unknown outputs, wrong sizes in tests). At most 255 bytes.
void append_raw_packet(std::vector<std::uint8_t>& out, std::uint16_t xdi, std::span<const std::uint8_t> data);

}  // namespace tumble::mti
