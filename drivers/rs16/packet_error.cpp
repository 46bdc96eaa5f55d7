#include "drivers/rs16/packet_error.hpp"

namespace tumble::rs16 {

void count(PacketError e, BadPackets& bad) {
  switch (e) {
    case PacketError::None: break;
    case PacketError::WrongSize: ++bad.wrong_size; break;
    case PacketError::WrongMagic: ++bad.wrong_magic; break;
    case PacketError::WrongTail: ++bad.wrong_tail; break;
    case PacketError::BadTimestamp: ++bad.bad_timestamp; break;
    case PacketError::NoValidBlocks: ++bad.no_valid_blocks; break;
  }
}

}  // namespace tumble::rs16
