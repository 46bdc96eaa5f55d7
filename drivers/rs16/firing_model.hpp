// When each of a packet's returns was fired and at which azimuth (docs/sensors.md,
// "RS-16: per-point time and azimuth"): 16 lasers fire 2.8 us apart, one
// firing sequence every 55.5 us.
#pragma once

#include <array>
#include <cstdint>

#include "drivers/rs16/packet_layout.hpp"

namespace tumble::rs16 {

enum class ReturnMode : std::uint8_t { Dual = 0, Strongest = 1, Last = 2 };

inline constexpr double kSequencePeriod_s = 55.5e-6;
inline constexpr double kLaserPeriod_s = 2.8e-6;
// Above this a block-to-block azimuth step is the edge of a restricted FOV,
// not motion: interpolation uses the nominal step instead.
inline constexpr double kFovGapThreshold_deg = 1.0;

// Single return: a block holds two firing sequences; dual: one sequence, both returns.
constexpr int sequences_per_block(ReturnMode mode) { return mode == ReturnMode::Dual ? 1 : 2; }
constexpr double block_period_s(ReturnMode mode) { return kSequencePeriod_s * sequences_per_block(mode); }
// The packet leaves the lidar after its last firing: this long after the header time.
constexpr double packet_duration_s(ReturnMode mode) { return block_period_s(mode) * kBlocks; }

// Per channel of a block: firing time after the block's first firing, and the
// fraction of the block's azimuth step the head has turned by then.
struct ChannelTiming {
  std::array<double, kChannelsPerBlock> offset_s{};
  std::array<double, kChannelsPerBlock> azimuth_fraction{};
};

constexpr ChannelTiming channel_timing(ReturnMode mode) {
  ChannelTiming t;
  for (int c = 0; c < kChannelsPerBlock; ++c) {
    const int sequence = mode == ReturnMode::Dual ? 0 : c / kLasers;
    t.offset_s[c] = kSequencePeriod_s * sequence + kLaserPeriod_s * (c % kLasers);
    t.azimuth_fraction[c] = t.offset_s[c] / block_period_s(mode);
  }
  return t;
}

// Azimuth step per block at rpm, in 0.01 deg units (39.96 at 600 rpm, single return).
constexpr double nominal_block_step(double rpm, ReturnMode mode) {
  return rpm * (kAzimuthUnitsPerTurn / 60.0) * block_period_s(mode);
}

// The head's turn from one block azimuth to the next (0.01 deg units, wrapped to
// [0, 36000)); steps above the FOV-gap threshold are replaced by the nominal step.
inline double interpolation_step(std::uint16_t azimuth, std::uint16_t next_azimuth, double nominal_step) {
  int step = int{next_azimuth} - int{azimuth};
  if (step < 0) step += kAzimuthUnitsPerTurn;
  return step > kFovGapThreshold_deg * 100.0 ? nominal_step : step;
}

}  // namespace tumble::rs16
