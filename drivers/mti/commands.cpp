#include "drivers/mti/commands.hpp"

#include <stdexcept>

#include "drivers/mti/baud.hpp"
#include "drivers/mti/big_endian.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/xbus_frame.hpp"

namespace tumble::mti {

std::vector<std::uint8_t> encode_wake_up_ack() { return encode_xbus_frame(mid::kWakeUpAck, {}); }
std::vector<std::uint8_t> encode_go_to_config() { return encode_xbus_frame(mid::kGoToConfig, {}); }
std::vector<std::uint8_t> encode_go_to_measurement() { return encode_xbus_frame(mid::kGoToMeasurement, {}); }
std::vector<std::uint8_t> encode_req_device_id() { return encode_xbus_frame(mid::kReqDeviceId, {}); }
std::vector<std::uint8_t> encode_req_product_code() { return encode_xbus_frame(mid::kReqProductCode, {}); }
std::vector<std::uint8_t> encode_req_firmware_rev() { return encode_xbus_frame(mid::kReqFirmwareRev, {}); }
std::vector<std::uint8_t> encode_reset() { return encode_xbus_frame(mid::kReset, {}); }

std::vector<std::uint8_t> encode_set_output_configuration(std::span<const OutputSetting> settings) {
  return encode_xbus_frame(mid::kSetOutputConfiguration, encode_output_configuration(settings));
}

std::vector<std::uint8_t> encode_set_baudrate(std::uint32_t baud) {
  const auto code = baud_code(baud);
  if (!code) throw std::invalid_argument("the MTi has no code for " + std::to_string(baud) + " baud");
  const std::uint8_t payload[] = {*code};
  return encode_xbus_frame(mid::kSetBaudrate, payload);
}

std::string FirmwareRevision::text() const {
  std::string t = std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(revision);
  if (build != 0 || svn_revision != 0) t += " build " + std::to_string(build) + " rev " + std::to_string(svn_revision);
  return t;
}

std::optional<std::uint32_t> parse_device_id(std::span<const std::uint8_t> payload) {
  if (payload.size() != 4) return std::nullopt;
  return read_u32_be(payload.data());
}

std::optional<FirmwareRevision> parse_firmware_revision(std::span<const std::uint8_t> payload) {
  if (payload.size() != 3 && payload.size() != 11) return std::nullopt;
  FirmwareRevision fw;
  fw.major = payload[0];
  fw.minor = payload[1];
  fw.revision = payload[2];
  if (payload.size() == 11) {
    fw.build = read_u32_be(payload.data() + 3);
    fw.svn_revision = read_u32_be(payload.data() + 7);
  }
  return fw;
}

std::string parse_product_code(std::span<const std::uint8_t> payload) {
  std::string code(payload.begin(), payload.end());
  while (!code.empty() && (code.back() == ' ' || code.back() == '\0')) code.pop_back();
  return code;
}

}  // namespace tumble::mti
