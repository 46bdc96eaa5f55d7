// Walks the packet chain of one MTData2 payload: [XDI u16][size u8][data].
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace tumble::mti {

struct MtData2Packet {
  std::uint16_t xdi = 0;
  std::span<const std::uint8_t> data;
};

class MtData2PacketReader {
 public:
  explicit MtData2PacketReader(std::span<const std::uint8_t> payload) : payload_(payload) {}
  // The next packet, or nullopt at the end or when the chain is cut short.
  std::optional<MtData2Packet> next();
  // A packet header or data ran past the end of the payload.
  bool truncated() const { return truncated_; }

 private:
  std::span<const std::uint8_t> payload_;
  std::size_t pos_ = 0;
  bool truncated_ = false;
};

}  // namespace tumble::mti
