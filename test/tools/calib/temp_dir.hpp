// Scratch folders, file writing and simulated still recordings for the tumble-calib tests.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include <yaml-cpp/yaml.h>

#include "test/temp_dir.hpp"
#include "tools/sim/run_writer.hpp"
#include "tools/sim/scenario.hpp"
#include "tools/sim/sim_run.hpp"

namespace tumble::calib::test {

using tumble::test::TempDir;

inline void write_file(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// A simulated recording of a rig standing still in the garage for duration_s.
inline void write_still_garage_run(const std::filesystem::path& dir, double duration_s) {
  const std::string yaml = "scene: garage\n"
                           "motion: {type: static, duration_s: " + std::to_string(duration_s) +
                           ", origin: {xyz_m: [-12, 0, 1.2]}}\n"
                           "seed: 3\n";
  sim::write_run(sim::SimRun(sim::parse_scenario(YAML::Load(yaml), "still.yaml", sim::sim_data_dir("scenes"))), dir);
}

}  // namespace tumble::calib::test
