// Big-endian reads and writes on byte spans: Xbus and MTData2 are big-endian
// throughout. Callers check sizes first; these never bounds-check.
#pragma once

#include <cstdint>
#include <vector>

namespace tumble::mti {

inline std::uint16_t read_u16_be(const std::uint8_t* p) {
  return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}

inline std::uint32_t read_u32_be(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
}

inline std::uint64_t read_u64_be(const std::uint8_t* p) {
  return (std::uint64_t{read_u32_be(p)} << 32) | read_u32_be(p + 4);
}

inline void append_u16_be(std::vector<std::uint8_t>& out, std::uint16_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v));
}

inline void append_u32_be(std::vector<std::uint8_t>& out, std::uint32_t v) {
  append_u16_be(out, static_cast<std::uint16_t>(v >> 16));
  append_u16_be(out, static_cast<std::uint16_t>(v));
}

inline void append_u64_be(std::vector<std::uint8_t>& out, std::uint64_t v) {
  append_u32_be(out, static_cast<std::uint32_t>(v >> 32));
  append_u32_be(out, static_cast<std::uint32_t>(v));
}

}  // namespace tumble::mti
