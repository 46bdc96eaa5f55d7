// Byte layout of the RS-16's two UDP packets (docs/sensors.md). All
// multi-byte fields are big-endian.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace tumble::rs16 {

inline constexpr std::size_t kPacketSize = 1248;
inline constexpr int kLasers = 16;
inline constexpr int kBlocks = 12;
inline constexpr int kChannelsPerBlock = 32;
inline constexpr int kMaxPointsPerPacket = kBlocks * kChannelsPerBlock;

inline constexpr std::array<std::uint8_t, 8> kMsopMagic{0x55, 0xAA, 0x05, 0x0A, 0x5A, 0xA5, 0x50, 0xA0};
inline constexpr std::array<std::uint8_t, 2> kMsopTail{0x00, 0xFF};
inline constexpr std::array<std::uint8_t, 2> kBlockFlag{0xFF, 0xEE};
inline constexpr std::size_t kMsopTimeOffset = 20;
inline constexpr std::size_t kMsopLidarTypeOffset = 30;
inline constexpr std::uint8_t kLidarTypeRs16 = 0x01;
inline constexpr std::size_t kMsopTemperatureOffset = 38;
inline constexpr std::size_t kFirstBlockOffset = 42;
inline constexpr std::size_t kBlockSize = 100;
inline constexpr std::size_t kBlockAzimuthOffset = 2;
inline constexpr std::size_t kBlockChannelsOffset = 4;
inline constexpr std::size_t kChannelSize = 3;
inline constexpr std::uint16_t kAzimuthUnitsPerTurn = 36000;  // 0.01 deg

inline constexpr std::array<std::uint8_t, 8> kDifopMagic{0xA5, 0xFF, 0x00, 0x5A, 0x11, 0x11, 0x55, 0x55};
inline constexpr std::array<std::uint8_t, 2> kDifopTail{0x0F, 0xF0};
inline constexpr std::size_t kDifopRpmOffset = 8;
// Bytes 41..43 of the top-board firmware field (40..44) tell the range resolution.
inline constexpr std::size_t kDifopTopFirmwareOffset = 41;
inline constexpr std::size_t kDifopSerialOffset = 292;
inline constexpr std::size_t kDifopReturnModeOffset = 300;
inline constexpr std::size_t kDifopTimeOffset = 303;
inline constexpr std::size_t kDifopVerticalAnglesOffset = 1165;
inline constexpr double kVerticalAngleUnitDeg = 0.0001;

inline constexpr std::size_t kTailOffset = 1246;
inline constexpr std::size_t kUtcTimeSize = 10;

inline std::uint16_t read_u16_be(std::span<const std::uint8_t> b, std::size_t offset) {
  return static_cast<std::uint16_t>((b[offset] << 8) | b[offset + 1]);
}

inline std::uint32_t read_u24_be(std::span<const std::uint8_t> b, std::size_t offset) {
  return (std::uint32_t{b[offset]} << 16) | (std::uint32_t{b[offset + 1]} << 8) | b[offset + 2];
}

inline void write_u16_be(std::span<std::uint8_t> b, std::size_t offset, std::uint16_t v) {
  b[offset] = static_cast<std::uint8_t>(v >> 8);
  b[offset + 1] = static_cast<std::uint8_t>(v & 0xFF);
}

inline void write_u24_be(std::span<std::uint8_t> b, std::size_t offset, std::uint32_t v) {
  b[offset] = static_cast<std::uint8_t>((v >> 16) & 0xFF);
  b[offset + 1] = static_cast<std::uint8_t>((v >> 8) & 0xFF);
  b[offset + 2] = static_cast<std::uint8_t>(v & 0xFF);
}

template <std::size_t N>
bool bytes_equal(std::span<const std::uint8_t> b, std::size_t offset, const std::array<std::uint8_t, N>& expected) {
  for (std::size_t i = 0; i < N; ++i) {
    if (b[offset + i] != expected[i]) return false;
  }
  return true;
}

}  // namespace tumble::rs16
