#include "core/odometry.hpp"

namespace tumble {

Odometry::Odometry(const OdometryParams& params, Clock clock, ParallelRunner& runner)
    : params_(params),
      clock_(std::move(clock)),
      fuser_(params.fuser),
      registration_(params, clock_, runner),
      pending_(params.max_pending_scans) {}

std::size_t Odometry::add_imu(const ImuSample& sample) {
  fuser_.add_imu(sample);
  if (!fuser_.initialized()) return 0;
  if (on_pose_ && !fuser_.trajectory().empty()) on_pose_(fuser_.trajectory().back());
  return process_ready_scans();
}

std::size_t Odometry::add_scan(const Scan& scan) {
  ++stats_.scans_received;
  if (scan.points.empty()) {
    ++stats_.scans_too_small;
    return 0;
  }
  if (!params_.wait_for_imu) {
    if (!fuser_.initialized() || fuser_.trajectory().empty()) {
      ++stats_.scans_before_init;
      return 0;
    }
    return process(scan) ? 1 : 0;
  }
  if (pending_count_ == pending_.size()) {  // drop the oldest
    pending_head_ = (pending_head_ + 1) % pending_.size();
    --pending_count_;
    ++stats_.scans_dropped_pending;
  }
  Scan& slot = pending_[(pending_head_ + pending_count_) % pending_.size()];
  slot.index = scan.index;
  slot.missing_packets = scan.missing_packets;
  slot.points.assign(scan.points.begin(), scan.points.end());
  ++pending_count_;
  return process_ready_scans();
}

bool Odometry::covered_by_imu(const Scan& scan) const {
  return fuser_.initialized() && !fuser_.trajectory().empty() &&
         fuser_.trajectory().t_end_s() >= scan.points.back().t_s;
}

std::size_t Odometry::process_ready_scans() {
  std::size_t processed = 0;
  while (pending_count_ > 0) {
    const Scan& scan = pending_[pending_head_];
    if (!fuser_.initialized()) {
      // The fuser is still in its static window: scans that end before its
      // trajectory can start will never be covered.
      ++stats_.scans_before_init;
    } else if (covered_by_imu(scan)) {
      if (scan.points.front().t_s < fuser_.trajectory().t_begin_s()) {
        ++stats_.scans_before_init;
      } else if (process(scan)) {
        ++processed;
      }
    } else {
      break;
    }
    pending_head_ = (pending_head_ + 1) % pending_.size();
    --pending_count_;
  }
  return processed;
}

bool Odometry::process(const Scan& scan) {
  ScanResult& result = result_;
  switch (registration_.process(scan, fuser_.trajectory(), result)) {
    case ScanOutcome::TooSmall:
      ++stats_.scans_too_small;
      return false;
    case ScanOutcome::OutOfOrder:
      ++stats_.scans_out_of_order;
      return false;
    case ScanOutcome::Registered:
      break;
  }
  if (!result.registered) ++stats_.registrations_failed;
  if (result.degeneracy.degenerate) ++stats_.registrations_degenerate;

  const double mark = now();
  if (result.registered)
    fuser_.correct_with_registered_pose(scan_correction_of(result));
  result.v_w = fuser_.trajectory().velocity_at(result.t_scan_start_s);
  if (result.timings.measured) {
    result.timings.fuser_correction_s = now() - mark;
    result.timings.total_s += result.timings.fuser_correction_s;
  }

  ++stats_.scans_processed;
  last_result_ = result;
  if (on_scan_) on_scan_(result);
  return true;
}

}  // namespace tumble
