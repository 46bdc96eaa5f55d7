// Frames the host sends during configuration, and parsers for the replies.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "drivers/mti/output_configuration.hpp"

namespace tumble::mti {

std::vector<std::uint8_t> encode_wake_up_ack();
std::vector<std::uint8_t> encode_go_to_config();
std::vector<std::uint8_t> encode_go_to_measurement();
std::vector<std::uint8_t> encode_req_device_id();
std::vector<std::uint8_t> encode_req_product_code();
std::vector<std::uint8_t> encode_req_firmware_rev();
std::vector<std::uint8_t> encode_reset();
std::vector<std::uint8_t> encode_set_output_configuration(std::span<const OutputSetting> settings);
// Throws std::invalid_argument for a baud rate the MTi has no code for.
std::vector<std::uint8_t> encode_set_baudrate(std::uint32_t baud);

struct FirmwareRevision {
  std::uint8_t major = 0, minor = 0, revision = 0;
  std::uint32_t build = 0, svn_revision = 0;  // 0 when the reply is the short 3-byte form
  std::string text() const;                   // "1.8.2 build 37 rev 70964"
};

// DeviceID (MID 0x01): 4 bytes. nullopt for any other size.
std::optional<std::uint32_t> parse_device_id(std::span<const std::uint8_t> payload);
// FirmwareRev (MID 0x13): 3 or 11 bytes.
std::optional<FirmwareRevision> parse_firmware_revision(std::span<const std::uint8_t> payload);
// ProductCode (MID 0x1D): ASCII, padded with spaces or NULs (trimmed here).
std::string parse_product_code(std::span<const std::uint8_t> payload);

}  // namespace tumble::mti
