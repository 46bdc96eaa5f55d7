// Motion YAML (format: tools/sim/README.md). Errors name the source, the key
// path and why: "rolling_cage.yaml: bounces.height_m: must be [min, max] with 0 < min <= max".
#pragma once

#include "tools/sim/motion.hpp"
#include "tools/sim/sim_config_error.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace tumble::sim {

struct MotionLoadOptions {
  std::string source_name = "motion";   // prefixes every error message (usually the file name)
  std::string key_path;                 // where `node` sits in that file ("motion"), prefixes key paths
  std::optional<std::uint64_t> seed;    // overrides every `seed:` key (bench runs differ by seed)
};

std::unique_ptr<Motion> load_motion(const YAML::Node& node);  // throws SimConfigError
std::unique_ptr<Motion> load_motion(const YAML::Node& node, const MotionLoadOptions& options);
std::unique_ptr<Motion> load_motion_file(const std::string& yaml_path, std::optional<std::uint64_t> seed = {});

}  // namespace tumble::sim
