// Parsers for the einride/xsens-go golden files (fixtures/mti/einride-mti-g-710):
//   output.golden         "Name(format):" headers, then "  Key:value" or "  value" lines;
//                         a blank line ends a message. Also outputconfig.golden.
//   output.client.golden  "MTData2", then pairs of tab-indented lines: name, then
//                         a value or "&{Key:value Key:value ...}".
//   messages.golden       one frame in hex per line.
#pragma once

#include <cctype>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "test/drivers/mti/mti_test_util.hpp"

namespace tumble::mti::test_util {

struct GoldenSection {
  std::string header;                                        // "Acceleration(FP1220)"
  std::vector<std::pair<std::string, std::string>> entries;  // key ("" for a bare value), value text
};
using GoldenMessage = std::vector<GoldenSection>;

// "X:-0.5" -> {"X", "-0.5"}; "2019-01-20T13:47:24Z" and "-0.5" are bare values.
inline std::pair<std::string, std::string> split_entry(const std::string& text) {
  const auto colon = text.find(':');
  if (colon == std::string::npos || colon == 0 || !std::isalpha(static_cast<unsigned char>(text[0])))
    return {"", text};
  for (std::size_t i = 0; i < colon; ++i)
    if (!std::isalnum(static_cast<unsigned char>(text[i]))) return {"", text};
  return {text.substr(0, colon), text.substr(colon + 1)};
}

inline std::vector<GoldenMessage> parse_output_golden(const std::filesystem::path& path) {
  std::vector<GoldenMessage> messages(1);
  for (const std::string& line : read_lines(path)) {
    if (line.empty()) {
      if (!messages.back().empty()) messages.emplace_back();
    } else if (line.rfind("  ", 0) == 0) {
      if (messages.back().empty()) throw std::runtime_error(path.string() + ": value before any header: " + line);
      messages.back().back().entries.push_back(split_entry(line.substr(2)));
    } else {
      if (line.back() != ':') throw std::runtime_error(path.string() + ": header without ':': " + line);
      messages.back().push_back({line.substr(0, line.size() - 1), {}});
    }
  }
  if (messages.back().empty()) messages.pop_back();
  return messages;
}

inline std::vector<GoldenMessage> parse_client_golden(const std::filesystem::path& path) {
  std::vector<GoldenMessage> messages;
  bool expect_name = true;
  for (const std::string& line : read_lines(path)) {
    if (line.empty()) continue;
    if (line == "MTData2") {
      messages.emplace_back();
      expect_name = true;
      continue;
    }
    if (line[0] != '\t' || messages.empty()) throw std::runtime_error(path.string() + ": unexpected line: " + line);
    const std::string text = line.substr(1);
    if (expect_name) {
      messages.back().push_back({text, {}});
    } else if (text.rfind("&{", 0) == 0 && text.back() == '}') {
      std::istringstream fields(text.substr(2, text.size() - 3));
      for (std::string field; fields >> field;) messages.back().back().entries.push_back(split_entry(field));
    } else {
      messages.back().back().entries.push_back({"", text});
    }
    expect_name = !expect_name;
  }
  return messages;
}

inline std::vector<std::vector<std::uint8_t>> parse_messages_golden(const std::filesystem::path& path) {
  std::vector<std::vector<std::uint8_t>> frames;
  for (const std::string& line : read_lines(path))
    if (!line.empty()) frames.push_back(from_hex(line));
  return frames;
}

}  // namespace tumble::mti::test_util
