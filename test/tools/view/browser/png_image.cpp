#include "test/tools/view/browser/png_image.hpp"

#include <zlib.h>

#include <array>
#include <cstdlib>
#include <cstring>

namespace tumble::test {
namespace {

std::uint32_t big_endian(const std::string& b, std::size_t at) {
  return (std::uint32_t(std::uint8_t(b[at])) << 24) | (std::uint32_t(std::uint8_t(b[at + 1])) << 16) |
         (std::uint32_t(std::uint8_t(b[at + 2])) << 8) | std::uint32_t(std::uint8_t(b[at + 3]));
}

std::uint8_t paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return static_cast<std::uint8_t>(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

}  // namespace

std::optional<RgbaImage> decode_png(const std::string& bytes) {
  static const char kSignature[] = "\x89PNG\r\n\x1a\n";
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kSignature, 8) != 0) return std::nullopt;
  RgbaImage image;
  int channels = 0;
  std::string compressed;
  for (std::size_t at = 8; at + 12 <= bytes.size();) {
    const std::uint32_t length = big_endian(bytes, at);
    const std::string type = bytes.substr(at + 4, 4);
    if (at + 12 + length > bytes.size()) return std::nullopt;
    const std::size_t data = at + 8;
    if (type == "IHDR") {
      image.width = static_cast<int>(big_endian(bytes, data));
      image.height = static_cast<int>(big_endian(bytes, data + 4));
      const int depth = std::uint8_t(bytes[data + 8]), colour = std::uint8_t(bytes[data + 9]);
      const int interlace = std::uint8_t(bytes[data + 12]);
      channels = colour == 2 ? 3 : colour == 6 ? 4 : 0;
      if (depth != 8 || channels == 0 || interlace != 0) return std::nullopt;
    } else if (type == "IDAT") {
      compressed.append(bytes, data, length);
    } else if (type == "IEND") {
      break;
    }
    at += 12 + length;
  }
  if (channels == 0 || image.width <= 0 || image.height <= 0) return std::nullopt;
  const std::size_t stride = static_cast<std::size_t>(image.width) * channels;
  std::vector<std::uint8_t> raw((stride + 1) * image.height);
  uLongf raw_size = raw.size();
  if (uncompress(raw.data(), &raw_size, reinterpret_cast<const Bytef*>(compressed.data()), compressed.size()) != Z_OK ||
      raw_size != raw.size())
    return std::nullopt;
  std::vector<std::uint8_t> previous(stride, 0), row(stride);
  image.rgba.resize(4 * static_cast<std::size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t* in = &raw[y * (stride + 1)];
    const int filter = in[0];
    for (std::size_t i = 0; i < stride; ++i) {
      const int a = i >= std::size_t(channels) ? row[i - channels] : 0, b = previous[i],
                c = i >= std::size_t(channels) ? previous[i - channels] : 0;
      const int x = in[1 + i];
      switch (filter) {
        case 0: row[i] = std::uint8_t(x); break;
        case 1: row[i] = std::uint8_t(x + a); break;
        case 2: row[i] = std::uint8_t(x + b); break;
        case 3: row[i] = std::uint8_t(x + (a + b) / 2); break;
        case 4: row[i] = std::uint8_t(x + paeth(a, b, c)); break;
        default: return std::nullopt;
      }
    }
    for (int px = 0; px < image.width; ++px)
      for (int k = 0; k < 4; ++k)
        image.rgba[4 * (std::size_t(y) * image.width + px) + k] = k < channels ? row[px * channels + k] : 255;
    previous = row;
  }
  return image;
}

std::string decode_base64(const std::string& text) {
  std::array<int, 256> value;
  value.fill(-1);
  const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  for (int i = 0; i < 64; ++i) value[std::uint8_t(alphabet[i])] = i;
  std::string out;
  int bits = 0, buffered = 0;
  for (const char c : text) {
    const int v = value[std::uint8_t(c)];
    if (v < 0) continue;  // padding, line breaks
    buffered = (buffered << 6) | v;
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((buffered >> bits) & 0xff));
    }
  }
  return out;
}

}  // namespace tumble::test
