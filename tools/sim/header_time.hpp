// The RS-16's UTC header time inside an MSOP or DIFOP payload, moved as a
// clock jump or a restarted unit would move it (`tumble-sim faults
// --lidar-clock-jump`, `tumble-sim live --lidar-restart`).
#pragma once

#include <cstdint>
#include <span>

namespace tumble::sim {

// False when the payload is too short or carries no valid time (left as it
// was). The UDP checksum is not refreshed: the simulator sends none (0), as
// IPv4 allows.
bool shift_header_time(std::span<std::uint8_t> payload, bool is_msop, std::int64_t shift_ns);

}  // namespace tumble::sim
