// --scan-log: one CSV row per scan the registration processed, for
// evaluation tools: how the registration went and what each stage cost.
// Columns: scan_index,t_s,registered,converged,iterations,inlier_ratio,
// residual_m,degeneracy,matched_ratio,correction_m,correction_deg (ICP's
// pose from the IMU-propagated one),points_in,points_used,sigma_s_median_m,
// <stage>_ms for each stage name, total_ms, latency_ms (scan complete →
// handed to the publisher). Written atomically like the trajectory file.
#pragma once

#include <string>
#include <vector>

#include "daemon/atomic_file.hpp"
#include "daemon/lcm_publisher.hpp"

namespace tumble::daemon {

class ScanLog : public RegistrationObserver {
 public:
  ScanLog(std::string path, const std::vector<std::string>& stage_names);

  void on_registration(const RegistrationRecord& registration) override;
  void commit() { file_.commit(); }
  const std::string& path() const { return file_.path(); }

 private:
  AtomicFile file_;
};

}  // namespace tumble::daemon
