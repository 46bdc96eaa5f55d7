// The four number formats of MTData2 real values (XDI low 2 bits).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace tumble::mti {

enum class NumberFormat : std::uint8_t { Float32 = 0, Fp1220 = 1, Fp1632 = 2, Float64 = 3 };

inline constexpr std::uint16_t kNumberFormatMask = 0x0003;

inline NumberFormat number_format_of(std::uint16_t xdi) { return static_cast<NumberFormat>(xdi & kNumberFormatMask); }

// Bytes of one value: 4, 4, 6, 8.
std::size_t number_format_bytes(NumberFormat f);
std::string_view number_format_name(NumberFormat f);

// Decodes one value; p must hold number_format_bytes(f) bytes. Every format is
// exact in a double (Fp16.32 has 48 significant bits).
double read_real(const std::uint8_t* p, NumberFormat f);
// Encodes one value. Fixed-point formats round to nearest and saturate at
// their range ([-2048, 2048) for 12.20, [-32768, 32768) for 16.32).
void append_real(std::vector<std::uint8_t>& out, double value, NumberFormat f);

}  // namespace tumble::mti
