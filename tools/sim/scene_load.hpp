// Scene YAML (format: tools/sim/README.md). Every error names the file, the
// key path and why, e.g. "garage.yaml: objects[3].size_m: must be 3 positive numbers".
#pragma once

#include "tools/sim/scene.hpp"
#include "tools/sim/sim_config_error.hpp"

#include <yaml-cpp/yaml.h>

#include <string>

namespace tumble::sim {

Scene load_scene(const std::string& yaml_path);                               // throws SimConfigError
Scene parse_scene(const YAML::Node& root, const std::string& source_name);    // source_name prefixes errors

}  // namespace tumble::sim
