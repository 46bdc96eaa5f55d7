// --scan-log: one CSV row per scan the registration processed, for
// evaluation tools: how the registration went, how the health machine judged
// it, and what each stage cost. Columns: the header line (daemon/README.md
// lists them); good_scan is 1 where the scan counts as good toward `tracking`
// and 0 where it puts tumbled in `degraded` (scan_verdict.hpp), under the
// config's daemon.health limits. Written atomically like the trajectory file.
#pragma once

#include <string>
#include <vector>

#include "daemon/atomic_file.hpp"
#include "daemon/config.hpp"
#include "daemon/lcm_publisher.hpp"

namespace tumble::daemon {

class ScanLog : public RegistrationObserver {
 public:
  ScanLog(std::string path, const std::vector<std::string>& stage_names, const HealthConfig& health);

  void on_registration(const RegistrationRecord& registration) override;
  void commit() { file_.commit(); }
  const std::string& path() const { return file_.path(); }

 private:
  AtomicFile file_;
  HealthConfig health_;
};

}  // namespace tumble::daemon
