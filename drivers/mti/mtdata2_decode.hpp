// Decodes MTData2 (MID 0x36) payloads into MtData2. Unknown outputs are
// skipped by their size; a known output whose size disagrees with its XDI is
// skipped and counted; a chain cut short drops the whole message.
#pragma once

#include <cstdint>
#include <span>

#include "drivers/mti/mtdata2.hpp"

namespace tumble::mti {

struct MtData2DecodeStats {
  std::uint64_t messages = 0;            // decoded
  std::uint64_t truncated_messages = 0;  // packet chain ran past the payload: dropped
  std::uint64_t size_mismatches = 0;     // packets skipped: size disagrees with the XDI
  std::uint64_t unknown_packets = 0;     // packets skipped: XDI not decoded here
};

// Resets msg and fills it. Returns false (msg left empty) for a truncated chain.
bool decode_mtdata2(std::span<const std::uint8_t> payload, MtData2& msg, MtData2DecodeStats& stats);

}  // namespace tumble::mti
