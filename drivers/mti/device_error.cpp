#include "drivers/mti/device_error.hpp"

namespace tumble::mti {

std::string_view error_code_name(std::uint8_t code) {
  switch (code) {
    case 3: return "period invalid";
    case 4: return "message invalid";
    case 30: return "timer overflow";
    case 32: return "baud rate invalid";
    case 33: return "parameter invalid";
    case 40: return "device error";
    case 41: return "data overflow";
    case 42: return "buffer overflow";
    default: return "unknown error";
  }
}

std::string describe_error(std::span<const std::uint8_t> payload) {
  if (payload.empty()) return "error without a code";
  return "error " + std::to_string(payload[0]) + " (" + std::string(error_code_name(payload[0])) + ")";
}

}  // namespace tumble::mti
