#include "drivers/mti/number_format.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "drivers/mti/big_endian.hpp"

namespace tumble::mti {
namespace {

constexpr double kFp1220Scale = 1048576.0;     // 2^20
constexpr double kFp1632Scale = 4294967296.0;  // 2^32

// Rounds value * scale to the nearest integer within [lo, hi]; NaN gives 0.
std::int64_t to_fixed(double value, double scale, std::int64_t lo, std::int64_t hi) {
  if (std::isnan(value)) return 0;
  const double scaled = std::round(value * scale);
  if (scaled <= static_cast<double>(lo)) return lo;
  if (scaled >= static_cast<double>(hi)) return hi;
  return static_cast<std::int64_t>(scaled);
}

}  // namespace

std::size_t number_format_bytes(NumberFormat f) {
  switch (f) {
    case NumberFormat::Float32: return 4;
    case NumberFormat::Fp1220: return 4;
    case NumberFormat::Fp1632: return 6;
    case NumberFormat::Float64: return 8;
  }
  return 4;
}

std::string_view number_format_name(NumberFormat f) {
  switch (f) {
    case NumberFormat::Float32: return "Float32";
    case NumberFormat::Fp1220: return "Fp1220";
    case NumberFormat::Fp1632: return "Fp1632";
    case NumberFormat::Float64: return "Float64";
  }
  return "?";
}

double read_real(const std::uint8_t* p, NumberFormat f) {
  switch (f) {
    case NumberFormat::Float32: return static_cast<double>(std::bit_cast<float>(read_u32_be(p)));
    case NumberFormat::Fp1220: return static_cast<double>(static_cast<std::int32_t>(read_u32_be(p))) / kFp1220Scale;
    case NumberFormat::Fp1632: {
      // The 32-bit fraction comes first, then the signed 16-bit integer part.
      const std::uint32_t fraction = read_u32_be(p);
      const auto integer = static_cast<std::int16_t>(read_u16_be(p + 4));
      const std::int64_t fixed = static_cast<std::int64_t>(integer) * (std::int64_t{1} << 32) + fraction;
      return static_cast<double>(fixed) / kFp1632Scale;
    }
    case NumberFormat::Float64: return std::bit_cast<double>(read_u64_be(p));
  }
  return 0.0;
}

void append_real(std::vector<std::uint8_t>& out, double value, NumberFormat f) {
  switch (f) {
    case NumberFormat::Float32: {
      // A finite double beyond float's range has no float value: saturate.
      constexpr double kMax = std::numeric_limits<float>::max();
      const double v = std::isfinite(value) ? std::clamp(value, -kMax, kMax) : value;
      append_u32_be(out, std::bit_cast<std::uint32_t>(static_cast<float>(v)));
      return;
    }
    case NumberFormat::Fp1220: {
      const std::int64_t fixed = to_fixed(value, kFp1220Scale, INT32_MIN, INT32_MAX);
      append_u32_be(out, static_cast<std::uint32_t>(static_cast<std::int32_t>(fixed)));
      return;
    }
    case NumberFormat::Fp1632: {
      constexpr std::int64_t kMax = (std::int64_t{1} << 47) - 1;
      const std::int64_t fixed = to_fixed(value, kFp1632Scale, -kMax - 1, kMax);
      const auto bits = static_cast<std::uint64_t>(fixed);
      append_u32_be(out, static_cast<std::uint32_t>(bits));
      append_u16_be(out, static_cast<std::uint16_t>(bits >> 32));
      return;
    }
    case NumberFormat::Float64:
      append_u64_be(out, std::bit_cast<std::uint64_t>(value));
      return;
  }
}

}  // namespace tumble::mti
