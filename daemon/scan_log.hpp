// --scan-log: one CSV row per scan the registration processed, for
// evaluation tools: how the registration went, how the health machine judged
// it, and what each stage cost. Columns: scan_index, t_s (scan start),
// registered, converged, iterations, inlier_ratio, residual_m, degeneracy,
// matched_ratio, correction_m, correction_deg (ICP's pose from the
// IMU-propagated one), points_in, points_used, sigma_s_median_m,
// correction_{x,y,z}_m, expected_error_m, cov_t{xx,yy,zz,xy,xz,yz} (the
// published position covariance), map_points, map_seen_through,
// direction_unobserved, expected_error_icp_m, spin_rate_unmeasured (the gyro
// clipped about the lidar's spin axis during the scan), good_scan (1: a good
// scan under the config's daemon.health limits, scan_verdict.hpp; 0: not,
// which ends the run of good scans and degrades tumbled from tracking),
// translation_held (1: ICP held the translation along the scan's weakest
// direction at the prediction, IcpParams::hold_weak_translation_share),
// prediction_prior (1: the prediction was ICP's prior, position_uncertainty.hpp),
// expected_rotation_error_icp_deg (degrees: the square root of the largest
// eigenvalue of the rotation block of the covariance that gives
// expected_error_icp_m; the fuser's levelling goes by both),
// <stage>_ms per stage, total_ms, latency_ms (scan complete → handed to the
// publisher). Written atomically like the trajectory file.
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
