#include "daemon/status_aggregator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace tumble::daemon {

namespace {

double seconds(std::int64_t ns) { return static_cast<double>(ns) * 1e-9; }

bool fresh(std::int64_t last_ns, std::int64_t now_ns, double timeout_s) {
  return last_ns != 0 && seconds(now_ns - last_ns) <= timeout_s;
}

float rate(std::int64_t count_now, std::int64_t count_before, double period_s) {
  return period_s > 0.0 ? static_cast<float>(static_cast<double>(count_now - count_before) / period_s) : 0.0f;
}

}  // namespace

StatusAggregator::StatusAggregator(const HealthConfig& health, std::vector<std::string> stage_names,
                                   std::vector<NamedRing> rings, const PipelineCounters& counters,
                                   SpscRing<RegistrationRecord>& scan_reports, std::int64_t start_steady_ns,
                                   std::shared_ptr<spdlog::logger> logger)
    : health_(health),
      stage_names_(std::move(stage_names)),
      rings_(std::move(rings)),
      counters_(counters),
      scan_reports_(scan_reports),
      logger_(std::move(logger)),
      start_steady_ns_(start_steady_ns),
      previous_steady_ns_(start_steady_ns),
      state_since_steady_ns_(start_steady_ns) {
  stage_names_.resize(std::min(stage_names_.size(), RegistrationRecord::kMaxStages));
  stage_ms_.resize(stage_names_.size());
}

bool StatusAggregator::is_good(const RegistrationRecord& r) const {
  return r.converged && r.inlier_ratio >= health_.min_inlier_ratio && r.degeneracy >= health_.min_degeneracy;
}

void StatusAggregator::drain_scan_reports() {
  while (scan_reports_.pop_with([this](const RegistrationRecord& r) {
    const std::size_t stages = std::min<std::size_t>(r.num_stages, stage_ms_.size());
    for (std::size_t i = 0; i < stages; ++i) stage_ms_[i].add(r.stage_ms[i]);
    iterations_.add(static_cast<float>(r.iterations));
    inlier_ratio_.add(r.inlier_ratio);
    degeneracy_.add(r.degeneracy);
    if (is_good(r)) {
      ++consecutive_good_scans_;
    } else {
      consecutive_good_scans_ = 0;
      ++bad_scans_in_period_;
    }
  })) {
  }
}

void StatusAggregator::tick(std::int64_t now_steady_ns, std::int64_t utime, tumble::status_t& out) {
  drain_scan_reports();
  const double period_s = seconds(now_steady_ns - previous_steady_ns_);
  const PipelineCounters& c = counters_;
  const auto load = [](const std::atomic<std::int64_t>& a) { return a.load(std::memory_order_relaxed); };

  // Health.
  std::uint64_t drops = static_cast<std::uint64_t>(load(c.scans_dropped));
  for (const NamedRing& r : rings_)
    if (r.carries_sensor_data) drops += r.ring->dropped();
  HealthInputs in;
  in.imu_fresh = fresh(load(c.last_imu_steady_ns), now_steady_ns, health_.sensor_timeout_s);
  in.lidar_fresh = fresh(load(c.last_lidar_steady_ns), now_steady_ns, health_.sensor_timeout_s);
  in.fuser_initialised = c.fuser_initialised.load(std::memory_order_relaxed);
  in.bad_scans_in_period = bad_scans_in_period_;
  in.consecutive_good_scans = consecutive_good_scans_;
  in.data_dropped = drops != previous_drops_;
  const HealthLimits limits{health_.degraded_to_lost_s, health_.good_scans_to_recover};
  const HealthTransition next =
      input_ended_ ? HealthTransition{state_, {}}
                   : next_health_state(state_, seconds(now_steady_ns - state_since_steady_ns_), in, limits);
  if (next.state != state_) {
    const bool worse = next.state == HealthState::Degraded || next.state == HealthState::Lost;
    logger_->log(worse ? spdlog::level::warn : spdlog::level::info, "state {} -> {}: {}", to_string(state_),
                 to_string(next.state), next.reason);
    state_ = next.state;
    state_since_steady_ns_ = now_steady_ns;
  }

  // The message.
  out.utime = utime;
  out.state = static_cast<std::int8_t>(state_);
  out.state_name = to_string(state_);
  out.uptime_s = static_cast<float>(seconds(now_steady_ns - start_steady_ns_));
  const std::int64_t lidar_packets = load(c.lidar_packets);
  const std::int64_t imu_samples = load(c.imu_samples);
  const std::int64_t scans = load(c.scans_registered);
  out.lidar_packet_rate_hz = rate(lidar_packets, previous_lidar_packets_, period_s);
  out.imu_rate_hz = rate(imu_samples, previous_imu_samples_, period_s);
  out.scan_rate_hz = rate(scans, previous_scans_, period_s);
  out.lidar_packets = lidar_packets;
  out.lidar_bad_packets = load(c.lidar_bad_packets);
  out.lidar_missing_packets = load(c.lidar_missing_packets);
  out.lidar_foreign_packets = load(c.lidar_foreign_packets);
  out.imu_frames = load(c.imu_frames);
  out.imu_bad_frames = load(c.imu_bad_frames);
  out.imu_gaps = load(c.imu_gaps);
  out.lidar_duplicate_packets = load(c.lidar_duplicate_packets);
  out.lidar_late_packets = load(c.lidar_late_packets);
  out.lidar_late_packets_dropped = load(c.lidar_late_packets_dropped);
  out.scans_short_coverage = load(c.scans_short_coverage);
  out.imu_duplicate_frames = load(c.imu_duplicate_frames);
  out.imu_out_of_order_frames = load(c.imu_out_of_order_frames);
  out.scans_registered = scans;
  out.scans_dropped = load(c.scans_dropped);
  out.scans_short_trajectory = load(c.scans_short_trajectory);

  out.num_rings = static_cast<std::int16_t>(rings_.size());
  out.ring_name.resize(rings_.size());
  out.ring_fill.resize(rings_.size());
  out.ring_drops.resize(rings_.size());
  for (std::size_t i = 0; i < rings_.size(); ++i) {
    out.ring_name[i] = rings_[i].name;
    out.ring_fill[i] = static_cast<float>(rings_[i].ring->fill());
    out.ring_drops[i] = static_cast<std::int64_t>(rings_[i].ring->dropped());
  }

  out.num_stages = static_cast<std::int16_t>(stage_names_.size());
  out.stage_name.resize(stage_names_.size());
  out.stage_median_ms.resize(stage_names_.size());
  out.stage_max_ms.resize(stage_names_.size());
  for (std::size_t i = 0; i < stage_names_.size(); ++i) {
    out.stage_name[i] = stage_names_[i];
    out.stage_median_ms[i] = stage_ms_[i].median();
    out.stage_max_ms[i] = stage_ms_[i].max();
    stage_ms_[i].reset();
  }
  out.icp_iterations_median = iterations_.median();
  out.inlier_ratio_median = inlier_ratio_.median();
  out.degeneracy_min = degeneracy_.min();
  iterations_.reset();
  inlier_ratio_.reset();
  degeneracy_.reset();

  for (std::size_t k = 0; k < 3; ++k) {
    out.accel_saturated_samples[k] = load(c.accel_saturated_samples[k]);
    out.gyro_saturated_samples[k] = load(c.gyro_saturated_samples[k]);
  }
  const auto clock = [](const std::atomic<double>& a) { return a.load(std::memory_order_relaxed); };
  out.imu_clock_offset_s = clock(c.imu_clock.offset_s);
  out.imu_clock_drift_ppm = clock(c.imu_clock.drift_ppm);
  out.imu_clock_jitter_s = clock(c.imu_clock.jitter_s);
  out.lidar_clock_offset_s = clock(c.lidar_clock.offset_s);
  out.lidar_clock_drift_ppm = clock(c.lidar_clock.drift_ppm);
  out.lidar_clock_jitter_s = clock(c.lidar_clock.jitter_s);

  summary_ = fmt::format("{}; IMU {:.0f} Hz, lidar {:.0f} packets/s, {:.1f} scans/s, {} dropped", to_string(state_),
                         out.imu_rate_hz, out.lidar_packet_rate_hz, out.scan_rate_hz, drops);

  previous_steady_ns_ = now_steady_ns;
  previous_lidar_packets_ = lidar_packets;
  previous_imu_samples_ = imu_samples;
  previous_scans_ = scans;
  previous_drops_ = drops;
  bad_scans_in_period_ = 0;
}

}  // namespace tumble::daemon
