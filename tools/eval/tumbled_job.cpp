#include "tools/eval/tumbled_job.hpp"

#include <unistd.h>

#include <stdexcept>
#include <string>

#include "tools/eval/tum_file.hpp"

namespace tumble::eval {

std::string Variant::label() const { return model + (deskew ? "-deskew" : "-no-deskew"); }

JobPaths job_paths(const std::filesystem::path& out_dir, const std::string& run_name, const Variant& variant) {
  const std::filesystem::path dir = out_dir / "trajectories" / run_name;
  const std::string stem = variant.label();
  return JobPaths{dir / (stem + ".tum"), dir / (stem + ".scans.csv"), dir / (stem + ".log")};
}

std::vector<std::string> tumbled_argv(const TumbledSetup& setup, const BenchRun& run, const Variant& variant,
                                      const JobPaths& paths) {
  std::vector<std::string> argv = {setup.tumbled.string(),
                                   "--replay",
                                   (run.dir / "lidar.pcap").string(),
                                   (run.dir / "imu.pcap").string(),
                                   "--rate",
                                   "max",
                                   "--lcm-url",
                                   "memq://",
                                   "--log-level",
                                   "warn",
                                   "--model",
                                   variant.model,
                                   variant.deskew ? "--deskew" : "--no-deskew",
                                   "--trajectory-out",
                                   paths.trajectory.string(),
                                   "--scan-log",
                                   paths.scan_log.string()};
  if (setup.config) {
    argv.push_back("--config");
    argv.push_back(setup.config->string());
  }
  return argv;
}

std::optional<std::string> run_input_problem(const BenchRun& run) {
  std::error_code error;
  if (!std::filesystem::is_directory(run.dir, error)) return "run folder " + run.dir.string() + " is missing";
  for (const char* name : {"lidar.pcap", "imu.pcap", "ground_truth.tum"}) {
    const std::filesystem::path file = run.dir / name;
    if (!std::filesystem::is_regular_file(file, error)) return std::string("no ") + name + " in " + run.dir.string();
    if (access(file.c_str(), R_OK) != 0) return file.string() + " is not readable";
  }
  try {
    if (read_tum(run.dir / "ground_truth.tum").size() < 2)
      return "ground truth: " + (run.dir / "ground_truth.tum").string() + ": fewer than 2 poses";
  } catch (const std::exception& e) {
    return std::string("ground truth: ") + e.what();
  }
  return std::nullopt;
}

std::filesystem::path locate_tumbled(const std::filesystem::path& self_executable) {
  const std::filesystem::path here = self_executable.parent_path();
  const std::filesystem::path candidates[] = {here / "tumbled",
                                              here.parent_path().parent_path() / "daemon" / "tumbled"};
  std::string looked;
  for (const std::filesystem::path& candidate : candidates) {
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
    looked += (looked.empty() ? "" : ", ") + candidate.string();
  }
  throw std::runtime_error("tumbled not found (looked at " + looked + "); build it or pass --tumbled PATH");
}

std::filesystem::path copy_tumbled(const std::filesystem::path& tumbled, const std::filesystem::path& dir) {
  const std::filesystem::path copy = dir / ".tumbled";
  // Copied beside it, then renamed over it: an earlier evaluation may still
  // run the old copy, which cannot be opened for writing while it runs.
  const std::filesystem::path part = dir / (".tumbled." + std::to_string(getpid()));
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (!error) std::filesystem::copy_file(tumbled, part, std::filesystem::copy_options::overwrite_existing, error);
  if (!error) std::filesystem::rename(part, copy, error);
  if (error) throw std::runtime_error("cannot copy " + tumbled.string() + " to " + copy.string() + ": " + error.message());
  return copy;
}

}  // namespace tumble::eval
