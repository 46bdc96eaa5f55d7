// Splitting and number parsing shared by the file readers: locale-free
// (std::from_chars), so "1.5" means the same on every machine.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tumble::eval {

std::vector<std::string_view> split_whitespace(std::string_view line);

// Plain comma split (the files read here never quote); a trailing '\r' is dropped.
std::vector<std::string_view> split_commas(std::string_view line);

// The whole field must be a number (leading '+' allowed); nullopt otherwise.
std::optional<double> parse_double(std::string_view field);

// Quotes a CSV field when it holds a comma, a quote or a line break.
std::string csv_field(std::string_view text);

}  // namespace tumble::eval
