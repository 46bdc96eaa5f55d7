// SetOutputConfiguration (MID 0xC0) and its echo (0xC1): N x [XDI u16][rate u16].
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "drivers/mti/number_format.hpp"

namespace tumble::mti {

// Rate 0xFFFF: with every message (counters, status).
inline constexpr std::uint16_t kRateEveryMessage = 0xFFFF;

struct OutputSetting {
  std::uint16_t xdi = 0;
  std::uint16_t rate_hz = 0;
  friend bool operator==(const OutputSetting&, const OutputSetting&) = default;
};

std::vector<std::uint8_t> encode_output_configuration(std::span<const OutputSetting> settings);
// Throws std::invalid_argument when the payload is not a whole number of settings.
std::vector<OutputSetting> parse_output_configuration(std::span<const std::uint8_t> payload);

// What this driver configures: PacketCounter, SampleTimeFine, Acceleration,
// RateOfTurn, StatusWord; the IMU outputs at rate_hz in fmt.
std::vector<OutputSetting> imu_output_configuration(std::uint16_t rate_hz, NumberFormat fmt);

// "Acceleration(Fp1220)@400Hz, StatusWord@max": for logs and error messages.
std::string describe(const OutputSetting& s);
std::string describe(std::span<const OutputSetting> settings);

}  // namespace tumble::mti
