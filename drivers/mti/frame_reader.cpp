#include "drivers/mti/frame_reader.hpp"

#include <algorithm>
#include <cstring>

#include "drivers/mti/big_endian.hpp"

namespace tumble::mti {

void FrameReader::push(std::span<const std::uint8_t> read) {
  input_ = read;
  input_pos_ = 0;
  finished_ = false;
  stats_.bytes += read.size();
}

void FrameReader::reset() {
  stats_.bytes_discarded += end_ - begin_;
  begin_ = end_ = 0;
  input_ = {};
  input_pos_ = 0;
  finished_ = false;
}

bool FrameReader::refill() {
  if (input_pos_ >= input_.size()) return false;
  if (begin_ > 0) {
    std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
    end_ -= begin_;
    begin_ = 0;
  }
  const std::size_t n = std::min(buffer_.size() - end_, input_.size() - input_pos_);
  std::memcpy(buffer_.data() + end_, input_.data() + input_pos_, n);
  end_ += n;
  input_pos_ += n;
  return n > 0;
}

bool FrameReader::wait_or_give_up() {
  if (refill()) return true;
  if (!finished_ || begin_ == end_) return false;
  // A frame may hide behind a bogus long header that will never complete.
  reject_candidate(stats_.cut_off);
  return true;
}

// Drops only the preamble: the next frame may start inside the rejected one.
void FrameReader::reject_candidate(std::uint64_t& reason) {
  ++reason;
  ++begin_;
  ++stats_.bytes_discarded;
}

std::optional<XbusFrame> FrameReader::next() {
  for (;;) {
    const std::uint8_t* const start = buffer_.data() + begin_;
    const std::uint8_t* const stop = buffer_.data() + end_;
    const std::uint8_t* const preamble = std::find(start, stop, kPreamble);
    stats_.bytes_discarded += static_cast<std::size_t>(preamble - start);
    begin_ += static_cast<std::size_t>(preamble - start);
    const std::size_t available = end_ - begin_;
    const std::uint8_t* const f = buffer_.data() + begin_;

    if (available < 4) {
      if (!wait_or_give_up()) return std::nullopt;
      continue;
    }
    if (f[1] != kBusIdMaster && f[1] != kBusIdFirstDevice) {
      reject_candidate(stats_.bad_bus_id);
      continue;
    }
    std::size_t header_bytes = 4;
    std::size_t payload_bytes = f[3];
    if (f[3] == kExtendedLength) {
      if (available < 6) {
        if (!wait_or_give_up()) return std::nullopt;
        continue;
      }
      header_bytes = 6;
      payload_bytes = read_u16_be(f + 4);
      if (payload_bytes < kMinExtendedPayloadBytes || payload_bytes > kMaxPayloadBytes) {
        reject_candidate(stats_.bad_length);
        continue;
      }
    }
    const std::size_t frame_bytes = header_bytes + payload_bytes + 1;
    if (available < frame_bytes) {
      if (!wait_or_give_up()) return std::nullopt;
      continue;
    }
    unsigned sum = 0;
    for (std::size_t i = 1; i < frame_bytes; ++i) sum += f[i];
    if ((sum & 0xFF) != 0) {
      reject_candidate(stats_.bad_checksum);
      continue;
    }
    XbusFrame frame;
    frame.bus_id = f[1];
    frame.mid = f[2];
    frame.payload = {f + header_bytes, payload_bytes};
    frame.frame_bytes = frame_bytes;
    begin_ += frame_bytes;
    frame.bytes_after_in_read = (end_ - begin_) + (input_.size() - input_pos_);
    ++stats_.frames;
    return frame;
  }
}

}  // namespace tumble::mti
