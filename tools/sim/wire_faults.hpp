// Byte-level rewrites of single records for `tumble-sim faults`: what a
// broken sensor does to its own packets while its link stays up.
#pragma once

#include <cstdint>
#include <functional>
#include <span>

namespace tumble::sim {

// Every block of an MSOP payload at one azimuth (0.01 deg): the motor stood
// still while the lasers fired on. False when the payload is no MSOP packet.
bool stall_msop_azimuths(std::span<std::uint8_t> payload, std::uint16_t azimuth);

// A DIFOP payload with every vertical angle kRecalibratedAngleScale times as
// steep: another calibration, as a second unit or a glitch would send. False
// when the payload is no valid DIFOP with calibrated angles.
inline constexpr double kRecalibratedAngleScale = 1.05;
bool recalibrate_difop(std::span<std::uint8_t> payload);

// The last block azimuth of an MSOP payload (where a stall would hold the head).
std::uint16_t last_msop_azimuth(std::span<const std::uint8_t> payload);

// Writes NaN into the rate of turn (float32 RateOfTurn, x axis) of the
// MTData2 frames of a serial stream that pick() chooses (called once per
// such frame, in order), with each frame's checksum made good again:
// numbers a broken device could send. Returns how many frames were changed.
std::uint64_t poison_rate_of_turn(std::span<std::uint8_t> stream, const std::function<bool()>& pick);

}  // namespace tumble::sim
