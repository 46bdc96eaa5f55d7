#include "drivers/mti/xbus_frame.hpp"

#include <stdexcept>
#include <string>

namespace tumble::mti {

std::uint8_t xbus_checksum(std::uint8_t bus_id, std::uint8_t mid, std::span<const std::uint8_t> length_and_payload) {
  unsigned sum = bus_id + mid;
  for (const std::uint8_t b : length_and_payload) sum += b;
  return static_cast<std::uint8_t>(0x100 - (sum & 0xFF));
}

std::vector<std::uint8_t> encode_xbus_frame(std::uint8_t mid, std::span<const std::uint8_t> payload,
                                            std::uint8_t bus_id) {
  if (payload.size() > kMaxPayloadBytes)
    throw std::invalid_argument("Xbus payload of " + std::to_string(payload.size()) + " bytes exceeds " +
                                std::to_string(kMaxPayloadBytes));
  std::vector<std::uint8_t> frame;
  frame.reserve(payload.size() + 7);
  frame.push_back(kPreamble);
  frame.push_back(bus_id);
  frame.push_back(mid);
  if (payload.size() <= kMaxStandardPayloadBytes) {
    frame.push_back(static_cast<std::uint8_t>(payload.size()));
  } else {
    frame.push_back(kExtendedLength);
    frame.push_back(static_cast<std::uint8_t>(payload.size() >> 8));
    frame.push_back(static_cast<std::uint8_t>(payload.size()));
  }
  frame.insert(frame.end(), payload.begin(), payload.end());
  frame.push_back(xbus_checksum(bus_id, mid, std::span<const std::uint8_t>(frame).subspan(3)));
  return frame;
}

}  // namespace tumble::mti
