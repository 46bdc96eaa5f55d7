// Why a decoder rejected a packet, and the counter each reason goes to.
#pragma once

#include "drivers/rs16/decoder_stats.hpp"

namespace tumble::rs16 {

enum class PacketError { None, WrongSize, WrongMagic, WrongTail, BadTimestamp, NoValidBlocks };

void count(PacketError e, BadPackets& bad);

}  // namespace tumble::rs16
