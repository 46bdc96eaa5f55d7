#include "tools/sim/header_time.hpp"

#include "drivers/rs16/packet_layout.hpp"
#include "drivers/rs16/utc_time.hpp"

namespace tumble::sim {

bool shift_header_time(std::span<std::uint8_t> payload, bool is_msop, std::int64_t shift_ns) {
  const std::size_t offset = is_msop ? rs16::kMsopTimeOffset : rs16::kDifopTimeOffset;
  if (payload.size() < offset + rs16::kUtcTimeSize) return false;
  const std::span<std::uint8_t, rs16::kUtcTimeSize> field(payload.data() + offset, rs16::kUtcTimeSize);
  const auto t_ns = rs16::decode_utc_time_ns(field);
  if (!t_ns) return false;
  rs16::encode_utc_time_ns(*t_ns + shift_ns, field);
  return true;
}

}  // namespace tumble::sim
