#include "drivers/mti/mtdata2_packets.hpp"

#include "drivers/mti/big_endian.hpp"

namespace tumble::mti {

std::optional<MtData2Packet> MtData2PacketReader::next() {
  if (truncated_ || pos_ == payload_.size()) return std::nullopt;
  const std::size_t left = payload_.size() - pos_;
  if (left < 3 || left - 3 < payload_[pos_ + 2]) {
    truncated_ = true;
    return std::nullopt;
  }
  MtData2Packet packet;
  packet.xdi = read_u16_be(payload_.data() + pos_);
  packet.data = payload_.subspan(pos_ + 3, payload_[pos_ + 2]);
  pos_ += 3 + packet.data.size();
  return packet;
}

}  // namespace tumble::mti
