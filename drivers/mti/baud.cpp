#include "drivers/mti/baud.hpp"

#include <array>
#include <utility>

namespace tumble::mti {
namespace {

// Ascending; 921600 also has the legacy code 0x0A.
constexpr std::array<std::pair<std::uint32_t, std::uint8_t>, 13> kCodes{{
    {4800, 0x0B},
    {9600, 0x09},
    {14400, 0x08},
    {19200, 0x07},
    {28800, 0x06},
    {38400, 0x05},
    {57600, 0x04},
    {76800, 0x03},
    {115200, 0x02},
    {230400, 0x01},
    {460800, 0x00},
    {921600, 0x80},
    {2000000, 0x0C},
}};

bool carries(std::uint32_t baud, std::size_t frame_bytes, double rate_hz) {
  const double bits_per_s = static_cast<double>(frame_bytes) * 10.0 * rate_hz;  // 8N1: 10 bits a byte
  return bits_per_s <= kMaxLineLoad * baud;
}

}  // namespace

std::optional<std::uint8_t> baud_code(std::uint32_t baud) {
  for (const auto& [b, code] : kCodes)
    if (b == baud) return code;
  return std::nullopt;
}

std::optional<std::uint32_t> baud_from_code(std::uint8_t code) {
  if (code == 0x0A) return 921600;
  for (const auto& [b, c] : kCodes)
    if (c == code) return b;
  return std::nullopt;
}

std::optional<std::uint32_t> least_baud_for(std::size_t frame_bytes, double rate_hz) {
  for (const auto& [b, code] : kCodes)
    if (carries(b, frame_bytes, rate_hz)) return b;
  return std::nullopt;
}

std::string baud_problem(std::uint32_t baud, std::size_t frame_bytes, double rate_hz) {
  if (carries(baud, frame_bytes, rate_hz)) return {};
  std::string why = std::to_string(frame_bytes) + "-byte frames at " + std::to_string(static_cast<int>(rate_hz)) +
                    " Hz need ";
  if (const auto least = least_baud_for(frame_bytes, rate_hz))
    why += "at least " + std::to_string(*least) + " baud";
  else
    why += "more than any MTi baud rate";
  return why + ", not " + std::to_string(baud);
}

}  // namespace tumble::mti
