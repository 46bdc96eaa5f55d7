// From a decoded MTData2 message to tumble::ImuSample (all but its time).
#pragma once

#include <cstdint>

#include "core/types.hpp"
#include "drivers/mti/mtdata2.hpp"

namespace tumble::mti {

// StatusWord clip flags: the value on a flagged axis is not the truth (it can
// read beyond the range), so saturation comes from these bits, never a threshold.
inline constexpr int kStatusClipAccelFirstBit = 8;  // X, Y, Z = bits 8, 9, 10
inline constexpr int kStatusClipGyroFirstBit = 11;  // X, Y, Z = bits 11, 12, 13
inline constexpr std::uint32_t kStatusClipAny = 1u << 19;

// Acceleration + RateOfTurn, or DeltaV + DeltaQ: anything else (GNSS-only,
// orientation-only messages) is not an IMU sample.
bool has_imu_data(const MtData2& m);

// Fills accel, gyro, saturation flags and orientation of out; leaves out.t_s.
// DeltaV and DeltaQ are increments over one output period and become rates
// with output_period_s. Returns false when m is not an IMU sample.
bool fill_imu_sample(const MtData2& m, double output_period_s, ImuSample& out);

}  // namespace tumble::mti
