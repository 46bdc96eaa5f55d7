// `tumble-eval score`: one tumbled trajectory against its ground truth, and
// from the --scan-log CSV what its scans cost and how far its pose ran away
// while published as good. What `./tumble demo` prints.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tools/eval/drift.hpp"
#include "tools/eval/runaway.hpp"
#include "tools/eval/speed_report.hpp"

namespace tumble::eval {

struct RunScore {
  DriftResult drift;
  std::size_t scans = 0;       // rows of the scan log
  std::size_t registered = 0;  // of which registered
  std::size_t converged = 0;   // of which ICP converged
  std::vector<TimingStats> stages;
  std::optional<TimingStats> total;
  std::optional<TimingStats> latency;
  std::optional<Runaway> runaway;  // none without a scan log or its good_scan column
};

// Throws std::runtime_error naming the file that is missing or malformed, and
// std::invalid_argument when the trajectory does not overlap the ground truth.
RunScore score_run(const std::filesystem::path& ground_truth, const std::filesystem::path& trajectory,
                   const std::optional<std::filesystem::path>& scan_log, const DriftOptions& options);

std::string score_markdown(const RunScore& score);

}  // namespace tumble::eval
