// One Xbus frame: preamble, bus id, MID, length (extended above 254), data,
// checksum. Every frame the driver sends is built here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace tumble::mti {

inline constexpr std::uint8_t kPreamble = 0xFA;
inline constexpr std::uint8_t kBusIdMaster = 0xFF;
inline constexpr std::uint8_t kBusIdFirstDevice = 0x01;
inline constexpr std::uint8_t kExtendedLength = 0xFF;
inline constexpr std::size_t kMaxStandardPayloadBytes = 254;
inline constexpr std::size_t kMinExtendedPayloadBytes = 255;
inline constexpr std::size_t kMaxPayloadBytes = 2048;
inline constexpr std::size_t kMaxFrameBytes = 6 + kMaxPayloadBytes + 1;

// A frame as read off the line. The payload points into the reader's buffer and
// is valid until the reader is called again.
struct XbusFrame {
  std::uint8_t bus_id = kBusIdMaster;
  std::uint8_t mid = 0;
  std::span<const std::uint8_t> payload;
  std::size_t frame_bytes = 0;  // on the wire, preamble to checksum
  // Bytes the same serial read delivered after this frame's last byte: they
  // were on the wire after it, which places the frame in time within the read.
  std::size_t bytes_after_in_read = 0;
};

// The checksum byte that makes bus id .. checksum sum to 0 mod 256.
std::uint8_t xbus_checksum(std::uint8_t bus_id, std::uint8_t mid, std::span<const std::uint8_t> length_and_payload);

// Throws std::invalid_argument for a payload above 2048 bytes.
std::vector<std::uint8_t> encode_xbus_frame(std::uint8_t mid, std::span<const std::uint8_t> payload,
                                            std::uint8_t bus_id = kBusIdMaster);

}  // namespace tumble::mti
