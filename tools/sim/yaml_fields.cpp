#include "tools/sim/yaml_fields.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

namespace tumble::sim {

YamlPath YamlPath::key(std::string_view k) const {
  return {source, path.empty() ? std::string(k) : path + "." + std::string(k)};
}

YamlPath YamlPath::index(std::size_t i) const { return {source, path + "[" + std::to_string(i) + "]"}; }

void YamlPath::fail(const std::string& why) const {
  throw SimConfigError(source + ": " + (path.empty() ? std::string("(top level)") : path) + ": " + why);
}

YAML::Node load_yaml_file(const std::string& yaml_path) {
  const std::string name = std::filesystem::path(yaml_path).filename().string();
  if (!std::filesystem::exists(yaml_path)) throw SimConfigError(yaml_path + ": file not found");
  try {
    return YAML::LoadFile(yaml_path);
  } catch (const YAML::ParserException& e) {
    throw SimConfigError(name + ": line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  } catch (const YAML::BadFile&) {
    throw SimConfigError(yaml_path + ": cannot be read");
  }
}

void require_map(const YAML::Node& node, const YamlPath& at) {
  if (!node.IsMap()) at.fail("must be a map of key: value");
}

bool has_key(const YAML::Node& map, std::string_view key) { return static_cast<bool>(map[std::string(key)]); }

void check_keys(const YAML::Node& map, const YamlPath& at, std::initializer_list<std::string_view> allowed) {
  require_map(map, at);
  for (const auto& kv : map) {
    const std::string k = kv.first.as<std::string>();
    bool known = false;
    for (auto a : allowed) known = known || (a == k);
    if (known) continue;
    std::ostringstream why;
    why << "unknown key (allowed:";
    for (auto a : allowed) why << ' ' << a;
    why << ')';
    at.key(k).fail(why.str());
  }
}

namespace {

YAML::Node required(const YAML::Node& map, const YamlPath& at, std::string_view key) {
  require_map(map, at);
  YAML::Node n = map[std::string(key)];
  if (!n) at.key(key).fail("missing");
  return n;
}

double as_double(const YAML::Node& n, const YamlPath& at) {
  double v = 0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v)) at.fail("must be a finite number");
  return v;
}

}  // namespace

double read_double(const YAML::Node& map, const YamlPath& at, std::string_view key) {
  return as_double(required(map, at, key), at.key(key));
}

double read_double(const YAML::Node& map, const YamlPath& at, std::string_view key, double fallback) {
  return has_key(map, key) ? read_double(map, at, key) : fallback;
}

double read_positive(const YAML::Node& map, const YamlPath& at, std::string_view key) {
  const double v = read_double(map, at, key);
  if (!(v > 0)) at.key(key).fail("must be a positive number");
  return v;
}

double read_positive(const YAML::Node& map, const YamlPath& at, std::string_view key, double fallback) {
  return has_key(map, key) ? read_positive(map, at, key) : fallback;
}

double read_non_negative(const YAML::Node& map, const YamlPath& at, std::string_view key, double fallback) {
  if (!has_key(map, key)) return fallback;
  const double v = read_double(map, at, key);
  if (v < 0) at.key(key).fail("must be a number >= 0");
  return v;
}

int read_count(const YAML::Node& map, const YamlPath& at, std::string_view key, int fallback) {
  if (!has_key(map, key)) return fallback;
  const YAML::Node n = map[std::string(key)];
  int v = 0;
  if (!n.IsScalar() || !YAML::convert<int>::decode(n, v) || v < 0) at.key(key).fail("must be an integer >= 0");
  return v;
}

bool read_bool(const YAML::Node& map, const YamlPath& at, std::string_view key, bool fallback) {
  if (!has_key(map, key)) return fallback;
  const YAML::Node n = map[std::string(key)];
  bool v = false;
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) at.key(key).fail("must be true or false");
  return v;
}

std::string read_string(const YAML::Node& map, const YamlPath& at, std::string_view key) {
  const YAML::Node n = required(map, at, key);
  if (!n.IsScalar()) at.key(key).fail("must be a string");
  return n.Scalar();
}

std::string read_string(const YAML::Node& map, const YamlPath& at, std::string_view key, const std::string& fallback) {
  return has_key(map, key) ? read_string(map, at, key) : fallback;
}

std::uint64_t read_seed(const YAML::Node& map, const YamlPath& at, std::string_view key, std::uint64_t fallback) {
  if (!has_key(map, key)) return fallback;
  const YAML::Node n = map[std::string(key)];
  std::uint64_t v = 0;
  if (!n.IsScalar() || n.Scalar().empty() || n.Scalar()[0] == '-' || !YAML::convert<std::uint64_t>::decode(n, v))
    at.key(key).fail("must be an unsigned integer");
  return v;
}

Eigen::Vector3d read_vec3(const YAML::Node& map, const YamlPath& at, std::string_view key) {
  const YAML::Node n = required(map, at, key);
  const YamlPath here = at.key(key);
  if (!n.IsSequence() || n.size() != 3) here.fail("must be 3 numbers [x, y, z]");
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i) v[static_cast<Eigen::Index>(i)] = as_double(n[i], here.index(i));
  return v;
}

Eigen::Vector3d read_vec3(const YAML::Node& map, const YamlPath& at, std::string_view key,
                          const Eigen::Vector3d& fallback) {
  return has_key(map, key) ? read_vec3(map, at, key) : fallback;
}

std::pair<double, double> read_positive_range(const YAML::Node& map, const YamlPath& at, std::string_view key,
                                              std::pair<double, double> fallback) {
  if (!has_key(map, key)) return fallback;
  const YAML::Node n = map[std::string(key)];
  const YamlPath here = at.key(key);
  const char* why = "must be [min, max] with 0 < min <= max, or one positive number";
  std::pair<double, double> r;
  if (n.IsScalar()) {
    r.first = r.second = as_double(n, here);
  } else if (n.IsSequence() && n.size() == 2) {
    r = {as_double(n[0], here.index(0)), as_double(n[1], here.index(1))};
  } else {
    here.fail(why);
  }
  if (!(r.first > 0) || r.second < r.first) here.fail(why);
  return r;
}

}  // namespace tumble::sim
