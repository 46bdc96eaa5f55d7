#include "daemon/scan_log.hpp"

#include <fmt/format.h>

#include "core/angles.hpp"
#include "daemon/scan_verdict.hpp"
#include "daemon/steady_time.hpp"

namespace tumble::daemon {

ScanLog::ScanLog(std::string path, const std::vector<std::string>& stage_names, const HealthConfig& health)
    : file_(std::move(path)), health_(health) {
  fmt::print(file_.get(),
             "scan_index,t_s,registered,converged,iterations,inlier_ratio,residual_m,degeneracy,matched_ratio,"
             "correction_m,correction_deg,points_in,points_used,sigma_s_median_m,correction_x_m,correction_y_m,"
             "correction_z_m,expected_error_m,cov_txx,cov_tyy,cov_tzz,cov_txy,cov_txz,cov_tyz,map_points,map_seen_through,"
             "direction_unobserved,expected_error_icp_m,spin_rate_unmeasured,good_scan,translation_held,prediction_prior,"
             "expected_rotation_error_icp_deg,jumped,imu_bridged,awaiting_rest,velocity_unconfirmed");
  for (const std::string& name : stage_names) fmt::print(file_.get(), ",{}_ms", name);
  fmt::print(file_.get(), ",total_ms,latency_ms\n");
}

void ScanLog::on_registration(const RegistrationRecord& r) {
  if (file_.get() == nullptr) return;
  fmt::print(file_.get(), "{},{:.6f},{:d},{:d},{},{:.4f},{:.5f},{:.6g},{:.4f},{:.5f},{:.4f},{},{},{:.5f}", r.scan_index,
             r.t_s, r.registered, r.converged, r.iterations, r.inlier_ratio, r.residual_m, r.degeneracy,
             r.matched_ratio, r.correction_m, r.correction_deg, r.points_in, r.points_used, r.sigma_s_median_m);
  for (const float c : r.correction_w_m) fmt::print(file_.get(), ",{:.5f}", c);
  fmt::print(file_.get(), ",{:.5f}", r.expected_error_m);
  // The published position covariance (upper triangle), for checking it against ground truth.
  for (const std::size_t i : {0, 7, 14, 1, 2, 8}) fmt::print(file_.get(), ",{:.4g}", r.covariance[i]);
  fmt::print(file_.get(), ",{},{},{:d},{:.5f},{:d},{:d},{:d},{:d},{:.5f},{:d},{:d},{:d},{:d}", r.map_points,
             r.map_points_seen_through, r.direction_unobserved, r.expected_error_icp_m, r.spin_rate_unmeasured,
             scan_verdict(r, health_) == ScanVerdict::Good, r.held_translation_w != std::array<float, 3>{},
             r.prediction_prior, r.expected_rotation_error_icp_rad * kRadToDeg, r.jumped, r.imu_bridged,
             r.awaiting_rest, r.velocity_unconfirmed);
  float total_ms = 0.0f;
  for (std::size_t i = 0; i < r.num_stages; ++i) {
    fmt::print(file_.get(), ",{:.3f}", r.stage_ms[i]);
    total_ms += r.stage_ms[i];
  }
  fmt::print(file_.get(), ",{:.3f},{:.3f}\n", total_ms, latency_ms_since(r.scan_complete_steady_ns));
}

}  // namespace tumble::daemon
