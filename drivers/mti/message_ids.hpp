// Xbus message identifiers (MT0101P). An acknowledgement is the request's MID + 1.
#pragma once

#include <cstdint>

namespace tumble::mti::mid {

inline constexpr std::uint8_t kReqDeviceId = 0x00;
inline constexpr std::uint8_t kDeviceId = 0x01;
inline constexpr std::uint8_t kGoToMeasurement = 0x10;
inline constexpr std::uint8_t kGoToMeasurementAck = 0x11;
inline constexpr std::uint8_t kReqFirmwareRev = 0x12;
inline constexpr std::uint8_t kFirmwareRev = 0x13;
inline constexpr std::uint8_t kSetBaudrate = 0x18;
inline constexpr std::uint8_t kSetBaudrateAck = 0x19;
inline constexpr std::uint8_t kReqProductCode = 0x1C;
inline constexpr std::uint8_t kProductCode = 0x1D;
inline constexpr std::uint8_t kGoToConfig = 0x30;
inline constexpr std::uint8_t kGoToConfigAck = 0x31;
inline constexpr std::uint8_t kMtData2 = 0x36;
inline constexpr std::uint8_t kWakeUp = 0x3E;
inline constexpr std::uint8_t kWakeUpAck = 0x3F;
inline constexpr std::uint8_t kReset = 0x40;
inline constexpr std::uint8_t kResetAck = 0x41;
inline constexpr std::uint8_t kError = 0x42;
inline constexpr std::uint8_t kSetOutputConfiguration = 0xC0;
inline constexpr std::uint8_t kOutputConfiguration = 0xC1;

}  // namespace tumble::mti::mid
