#include "drivers/mti/product_code.hpp"

#include <numbers>

#include "core/types.hpp"

namespace tumble::mti {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

std::optional<double> gyro_range_rad_s(char code) {
  switch (code) {
    case '0': return 1000.0 * kDegToRad;
    case '4': return 450.0 * kDegToRad;
    default: return std::nullopt;
  }
}

std::optional<double> accel_range_m_s2(char code) {
  switch (code) {
    case '5': return 5.0 * kStandardGravity_m_s2;
    case '8': return 20.0 * kStandardGravity_m_s2;
    default: return std::nullopt;
  }
}

}  // namespace

SensorRanges ranges_from_product_code(std::string_view product_code) {
  // The ranges are the last "A<digit>G<digit>" of the code (a suffix may follow).
  SensorRanges r;
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  if (product_code.size() < 4) return r;
  for (std::size_t i = product_code.size() - 4 + 1; i-- > 0;) {
    const std::string_view s = product_code.substr(i, 4);
    if (s[0] == 'A' && digit(s[1]) && s[2] == 'G' && digit(s[3])) {
      r.accel_m_s2 = accel_range_m_s2(s[1]);
      r.gyro_rad_s = gyro_range_rad_s(s[3]);
      break;
    }
  }
  return r;
}

}  // namespace tumble::mti
