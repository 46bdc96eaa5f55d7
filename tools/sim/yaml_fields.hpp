// Strict reading of simulator YAML: every value is looked up through a
// YamlPath so that any error names the file, the full key path and why.
#pragma once

#include "tools/sim/sim_config_error.hpp"

#include <Eigen/Core>
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace tumble::sim {

// Where a node sits: "garage.yaml" + "objects[3].size_m".
struct YamlPath {
  std::string source;
  std::string path;

  YamlPath key(std::string_view k) const;
  YamlPath index(std::size_t i) const;
  [[noreturn]] void fail(const std::string& why) const;  // throws SimConfigError("source: path: why")
};

// Parses a file; syntax errors become SimConfigError("file: line N: ...").
YAML::Node load_yaml_file(const std::string& yaml_path);

void require_map(const YAML::Node& node, const YamlPath& at);
// Rejects keys not in `allowed`, naming the key and listing the allowed ones.
void check_keys(const YAML::Node& map, const YamlPath& at, std::initializer_list<std::string_view> allowed);
bool has_key(const YAML::Node& map, std::string_view key);

double read_double(const YAML::Node& map, const YamlPath& at, std::string_view key);
double read_double(const YAML::Node& map, const YamlPath& at, std::string_view key, double fallback);
double read_positive(const YAML::Node& map, const YamlPath& at, std::string_view key);
double read_positive(const YAML::Node& map, const YamlPath& at, std::string_view key, double fallback);
double read_non_negative(const YAML::Node& map, const YamlPath& at, std::string_view key, double fallback);
int read_count(const YAML::Node& map, const YamlPath& at, std::string_view key, int fallback);  // >= 0
bool read_bool(const YAML::Node& map, const YamlPath& at, std::string_view key, bool fallback);
std::string read_string(const YAML::Node& map, const YamlPath& at, std::string_view key);
std::string read_string(const YAML::Node& map, const YamlPath& at, std::string_view key, const std::string& fallback);
std::uint64_t read_seed(const YAML::Node& map, const YamlPath& at, std::string_view key, std::uint64_t fallback);
Eigen::Vector3d read_vec3(const YAML::Node& map, const YamlPath& at, std::string_view key);
Eigen::Vector3d read_vec3(const YAML::Node& map, const YamlPath& at, std::string_view key, const Eigen::Vector3d& fallback);
// [min, max] with 0 < min <= max (or a single positive number meaning min = max).
std::pair<double, double> read_positive_range(const YAML::Node& map, const YamlPath& at, std::string_view key,
                                              std::pair<double, double> fallback);

}  // namespace tumble::sim
