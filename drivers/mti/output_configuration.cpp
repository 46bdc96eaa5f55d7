#include "drivers/mti/output_configuration.hpp"

#include "drivers/mti/big_endian.hpp"
#include "drivers/mti/xdi.hpp"

#include <cstdio>
#include <stdexcept>

namespace tumble::mti {

std::vector<std::uint8_t> encode_output_configuration(std::span<const OutputSetting> settings) {
  std::vector<std::uint8_t> out;
  out.reserve(settings.size() * 4);
  for (const OutputSetting& s : settings) {
    append_u16_be(out, s.xdi);
    append_u16_be(out, s.rate_hz);
  }
  return out;
}

std::vector<OutputSetting> parse_output_configuration(std::span<const std::uint8_t> payload) {
  if (payload.size() % 4 != 0)
    throw std::invalid_argument("output configuration of " + std::to_string(payload.size()) +
                                " bytes is not a whole number of 4-byte settings");
  std::vector<OutputSetting> settings;
  settings.reserve(payload.size() / 4);
  for (std::size_t i = 0; i < payload.size(); i += 4)
    settings.push_back({read_u16_be(payload.data() + i), read_u16_be(payload.data() + i + 2)});
  return settings;
}

std::vector<OutputSetting> imu_output_configuration(std::uint16_t rate_hz, NumberFormat fmt) {
  const auto f = static_cast<std::uint16_t>(fmt);
  return {{xdi::kPacketCounter, kRateEveryMessage},
          {xdi::kSampleTimeFine, kRateEveryMessage},
          {static_cast<std::uint16_t>(xdi::kAcceleration | f), rate_hz},
          {static_cast<std::uint16_t>(xdi::kRateOfTurn | f), rate_hz},
          {xdi::kStatusWord, kRateEveryMessage}};
}

std::string describe(const OutputSetting& s) {
  std::string text;
  if (const auto i = xdi::info(s.xdi)) {
    text = std::string(i->name);
    if (i->layout == xdi::Layout::Reals) {
      text += "(";
      if (i->has_coordinate_system)
        text += std::string(xdi::coordinate_system_name(xdi::coordinate_system_of(s.xdi))) + ",";
      text += std::string(number_format_name(number_format_of(s.xdi))) + ")";
    }
  } else {
    char hex[16];
    std::snprintf(hex, sizeof hex, "XDI 0x%04X", s.xdi);
    text = hex;
  }
  if (s.rate_hz == kRateEveryMessage) {
    text += "@max";
  } else {
    text += '@';
    text += std::to_string(s.rate_hz);
    text += "Hz";
  }
  return text;
}

std::string describe(std::span<const OutputSetting> settings) {
  std::string text;
  for (const OutputSetting& s : settings) {
    if (!text.empty()) text += ", ";
    text += describe(s);
  }
  return text.empty() ? "(none)" : text;
}

}  // namespace tumble::mti
