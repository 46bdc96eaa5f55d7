// The 10-byte UTC timestamp both RS-16 packets carry: year-2000, month, day,
// hour, minute, second (u8 each), millisecond u16, microsecond u16.
#pragma once

#include <cstdint>
#include <optional>
#include <span>

namespace tumble::rs16 {

// Nanoseconds since the Unix epoch, computed as timegm would (UTC, never the
// host time zone); nullopt when a field is out of its range.
std::optional<std::int64_t> decode_utc_time_ns(std::span<const std::uint8_t, 10> bytes);

// Writes t (years 2000..2255, truncated to whole microseconds).
void encode_utc_time_ns(std::int64_t t_ns, std::span<std::uint8_t, 10> bytes);

}  // namespace tumble::rs16
