// Line speed: the MTi's baud rate codes and whether a baud carries a rate.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace tumble::mti {

// SetBaudrate codes (MT0101P); nullopt for rates the MTi does not offer.
std::optional<std::uint8_t> baud_code(std::uint32_t baud);
std::optional<std::uint32_t> baud_from_code(std::uint8_t code);

// The stream may fill at most half the line: the rest is headroom for
// replies, GNSS frames and the device's own send jitter. At 400 Hz the 54-byte
// frame (216 kbit/s on the wire) needs 460800 baud, as Xsens recommends.
inline constexpr double kMaxLineLoad = 0.5;

// The least standard baud rate that carries frame_bytes at rate_hz; nullopt
// when none does.
std::optional<std::uint32_t> least_baud_for(std::size_t frame_bytes, double rate_hz);
// Empty when baud carries frame_bytes at rate_hz, else why not.
std::string baud_problem(std::uint32_t baud, std::size_t frame_bytes, double rate_hz);

}  // namespace tumble::mti
