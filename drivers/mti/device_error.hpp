// Error (MID 0x42) replies: one code byte.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace tumble::mti {

// "baud rate invalid" for 32 and so on; "unknown error" for codes not listed.
std::string_view error_code_name(std::uint8_t code);
// "error 32 (baud rate invalid)" from an Error payload.
std::string describe_error(std::span<const std::uint8_t> payload);

}  // namespace tumble::mti
