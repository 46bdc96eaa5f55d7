// YAML steps -> ScalarProfile, shared by the rail, the turntable, the cage's
// roll and the walk. Keys carry units: linear profiles use _m, _m_s, _m_s2;
// angular ones _rad, _rad_s, _rad_s2 (format: tools/sim/README.md).
#pragma once

#include "tools/sim/scalar_profile.hpp"
#include "tools/sim/yaml_fields.hpp"

namespace tumble::sim {

enum class ProfileUnits { Linear, Angular };

ScalarProfile read_profile(const YAML::Node& steps, const YamlPath& at, ProfileUnits units);

}  // namespace tumble::sim
