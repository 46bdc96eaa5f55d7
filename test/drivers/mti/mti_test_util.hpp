// Helpers shared by the MTi tests: hex, files, frames.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "drivers/mti/frame_reader.hpp"
#include "drivers/mti/xbus_frame.hpp"

namespace tumble::mti::test_util {

inline std::vector<std::uint8_t> from_hex(const std::string& hex) {
  if (hex.size() % 2 != 0) throw std::invalid_argument("odd hex length: " + hex);
  std::vector<std::uint8_t> bytes;
  for (std::size_t i = 0; i < hex.size(); i += 2)
    bytes.push_back(static_cast<std::uint8_t>(std::stoul(hex.substr(i, 2), nullptr, 16)));
  return bytes;
}

inline std::vector<std::uint8_t> read_file(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot read " + path.string());
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

inline std::vector<std::string> read_lines(const std::filesystem::path& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read " + path.string());
  std::vector<std::string> lines;
  for (std::string line; std::getline(f, line);) lines.push_back(line);
  return lines;
}

// A frame copied out of the reader (whose views die on the next call).
struct OwnedFrame {
  std::uint8_t bus_id = 0;
  std::uint8_t mid = 0;
  std::vector<std::uint8_t> payload;
  std::size_t frame_bytes = 0;
  std::size_t bytes_after_in_read = 0;
};

// Every frame of bytes, pushed in chunks of chunk_bytes (0 = all at once).
inline std::vector<OwnedFrame> read_frames(FrameReader& reader, const std::vector<std::uint8_t>& bytes,
                                           std::size_t chunk_bytes = 0) {
  std::vector<OwnedFrame> frames;
  const std::size_t step = chunk_bytes == 0 ? bytes.size() : chunk_bytes;
  for (std::size_t pos = 0; pos < bytes.size(); pos += step) {
    const std::size_t n = std::min(step, bytes.size() - pos);
    reader.push(std::span<const std::uint8_t>(bytes.data() + pos, n));
    while (const auto f = reader.next())
      frames.push_back({f->bus_id, f->mid, {f->payload.begin(), f->payload.end()}, f->frame_bytes,
                        f->bytes_after_in_read});
  }
  return frames;
}

inline std::vector<OwnedFrame> read_frames(const std::vector<std::uint8_t>& bytes, std::size_t chunk_bytes = 0) {
  FrameReader reader;
  return read_frames(reader, bytes, chunk_bytes);
}

inline void append(std::vector<std::uint8_t>& to, const std::vector<std::uint8_t>& bytes) {
  to.insert(to.end(), bytes.begin(), bytes.end());
}

}  // namespace tumble::mti::test_util
