// Incremental Xbus frame reader: bytes arrive one serial read at a time, in any
// split; frames come out whole. Garbage, bad checksums and impossible lengths
// are skipped (the reader resynchronises on the next preamble, re-scanning the
// bytes of the rejected frame) and counted. Fixed buffer: no allocation.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "drivers/mti/xbus_frame.hpp"

namespace tumble::mti {

struct FrameReaderStats {
  std::uint64_t bytes = 0;            // bytes pushed
  std::uint64_t bytes_discarded = 0;  // bytes that were not part of a good frame
  std::uint64_t frames = 0;           // good frames returned
  std::uint64_t bad_checksum = 0;     // candidate frames rejected, by reason
  std::uint64_t bad_length = 0;       // extended length outside 255..2048
  std::uint64_t bad_bus_id = 0;       // neither 0xFF nor 0x01 after a preamble
  std::uint64_t cut_off = 0;          // started but never completed: the stream ended
  std::uint64_t bad_frames() const { return bad_checksum + bad_length + bad_bus_id + cut_off; }
};

class FrameReader {
 public:
  // Hands the reader the bytes of one serial read. Call next() until it returns
  // nullopt before pushing the next read; the span must stay valid until then.
  void push(std::span<const std::uint8_t> read);
  // The next good frame, or nullopt when the pushed bytes hold no more.
  std::optional<XbusFrame> next();
  // No more bytes will come (end of a file): next() then also re-scans what
  // sits behind an incomplete frame and discards the incomplete rest.
  void finish() { finished_ = true; }
  // Forgets a partial frame (after a reconnect). Statistics are kept.
  void reset();
  // Bytes held back as the start of a frame not yet complete.
  std::size_t buffered_bytes() const { return end_ - begin_; }
  const FrameReaderStats& stats() const { return stats_; }

 private:
  // Tops the buffer up from the pushed read; false when nothing could be added.
  bool refill();
  // What to do when a candidate needs bytes that are not there (yet).
  bool wait_or_give_up();
  void reject_candidate(std::uint64_t& reason);

  // Twice the largest frame so that a rejected frame's bytes can be re-scanned
  // while the input keeps topping up the buffer.
  std::array<std::uint8_t, 2 * kMaxFrameBytes> buffer_{};
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  std::span<const std::uint8_t> input_;
  std::size_t input_pos_ = 0;
  bool finished_ = false;
  FrameReaderStats stats_;
};

}  // namespace tumble::mti
