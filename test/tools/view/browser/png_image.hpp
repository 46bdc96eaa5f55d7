// Decodes the PNGs Chromium's screenshots are (8-bit RGB or RGBA, not
// interlaced) into RGBA pixels, so a test can look at what a page drew.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tumble::test {

struct RgbaImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  // row-major, 4 bytes a pixel
  const std::uint8_t* at(int x, int y) const { return &rgba[4 * (static_cast<std::size_t>(y) * width + x)]; }
};

// nullopt: not a PNG of that kind, or corrupt.
std::optional<RgbaImage> decode_png(const std::string& bytes);

std::string decode_base64(const std::string& text);

}  // namespace tumble::test
