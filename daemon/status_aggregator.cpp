#include "daemon/status_aggregator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "daemon/scan_verdict.hpp"

namespace tumble::daemon {

namespace {

double seconds(std::int64_t ns) { return static_cast<double>(ns) * 1e-9; }

constexpr double kNeverHeard_s = std::numeric_limits<double>::infinity();

double silent_s(std::int64_t last_ns, std::int64_t now_ns) {
  return last_ns != 0 ? seconds(now_ns - last_ns) : kNeverHeard_s;
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

void StatusAggregator::drain_scan_reports(std::uint64_t until, std::int64_t now_ns) {
  while (reports_consumed_ < until && scan_reports_.pop_with([this, now_ns](const RegistrationRecord& r) {
    const std::size_t stages = std::min<std::size_t>(r.num_stages, stage_ms_.size());
    for (std::size_t i = 0; i < stages; ++i) stage_ms_[i].add(r.stage_ms[i]);
    iterations_.add(static_cast<float>(r.iterations));
    inlier_ratio_.add(r.inlier_ratio);
    degeneracy_.add(r.degeneracy);
    any_scan_reported_ = true;
    // Live, the health clock ticks once per status period: the scan's own completion time is finer.
    const bool stamped = !on_sensor_time_ && r.scan_complete_steady_ns != 0;
    newest_scan_ns_ = std::max(newest_scan_ns_, stamped ? r.scan_complete_steady_ns : now_ns);
    if (r.resets > resets_seen_) {
      resets_in_period_ += r.resets - resets_seen_;
      resets_seen_ = r.resets;
      newest_reset_reason_ = r.reset_reason;
    }
    if (r.map_initialised) new_map_at_resets_ = r.resets;
    if (r.registered) expected_error_max_m_ = std::max(expected_error_max_m_, r.expected_error_m);
    const ScanVerdict v = scan_verdict(r, health_);
    consecutive_good_scans_ = v == ScanVerdict::Good ? consecutive_good_scans_ + 1 : 0;
    worst_scan_in_period_ = std::max(worst_scan_in_period_, v);
  })) {
    ++reports_consumed_;
  }
}

std::uint64_t StatusAggregator::sensor_drops() const {
  const auto load = [](const std::atomic<std::int64_t>& a) { return a.load(std::memory_order_relaxed); };
  std::uint64_t drops = static_cast<std::uint64_t>(load(counters_.scans_dropped));
  for (const NamedRing& r : rings_)
    if (r.carries_sensor_data) drops += r.ring->dropped();
  return drops;
}

void StatusAggregator::evaluate_health(std::int64_t now_ns, double imu_silent_s, double lidar_silent_s,
                                       bool fuser_initialised, double foreign_lidar_rate_hz) {
  const std::uint64_t drops = sensor_drops();
  if (input_ended_) imu_silent_s = lidar_silent_s = 0.0;
  HealthInputs in;
  in.imu_fresh = imu_silent_s <= health_.sensor_timeout_s;
  in.lidar_fresh = lidar_silent_s <= health_.sensor_timeout_s;
  in.lidar_silent_s = lidar_silent_s;
  // Before the first scan nothing is late; after the input ended neither.
  in.scan_silent_s = any_scan_reported_ && !input_ended_ ? seconds(now_ns - newest_scan_ns_) : 0.0;
  // Good scans before a silence, or before a spell without scans, say nothing of the pose after it.
  if (!in.lidar_fresh || in.scan_silent_s >= health_.scan_timeout_s) consecutive_good_scans_ = 0;
  in.fuser_initialised = fuser_initialised;
  in.worst_scan_in_period = worst_scan_in_period_;
  in.consecutive_good_scans = consecutive_good_scans_;
  in.data_dropped = drops != previous_drops_for_health_;
  in.resets_in_period = resets_in_period_;
  in.reset_reason = to_string(newest_reset_reason_);
  // Lost without a reset (a silent lidar): the registration's reset comes later, with the next scan.
  if (state_ == HealthState::Lost && resets_in_period_ > 0) lost_at_resets_ = resets_seen_;
  in.new_map_since_lost = lost_at_resets_ > 0 && new_map_at_resets_ >= lost_at_resets_;
  in.second_lidar = !input_ended_ && foreign_lidar_rate_hz >= health_.second_lidar_rate_hz;
  const HealthLimits limits{health_.degraded_to_lost_s, health_.good_scans_to_recover,
                            health_.lidar_silent_to_lost_s, health_.scan_timeout_s};
  const HealthTransition next = next_health_state(state_, seconds(now_ns - state_since_steady_ns_), in, limits);
  if (next.state != state_) {
    const bool worse = next.state == HealthState::Degraded || next.state == HealthState::Lost;
    if (on_sensor_time_) {
      logger_->log(worse ? spdlog::level::warn : spdlog::level::info, "state {} -> {}: {} (data time {:.1f} s)",
                   to_string(state_), to_string(next.state), next.reason, seconds(now_ns - start_steady_ns_));
    } else {
      logger_->log(worse ? spdlog::level::warn : spdlog::level::info, "state {} -> {}: {}", to_string(state_),
                   to_string(next.state), next.reason);
    }
    if (next.state == HealthState::Lost) lost_at_resets_ = resets_in_period_ > 0 ? resets_seen_ : -1;
    state_ = next.state;
    state_since_steady_ns_ = now_ns;
    state_reason_ = next.reason;
  } else if (!next.reason.empty() && next.reason != state_reason_) {  // the same state for a new reason
    if (on_sensor_time_) {
      logger_->warn("state {}: {} (data time {:.1f} s)", to_string(state_), next.reason,
                    seconds(now_ns - start_steady_ns_));
    } else {
      logger_->warn("state {}: {}", to_string(state_), next.reason);
    }
    state_reason_ = next.reason;
  }
  if (next.pose_good) state_since_steady_ns_ = now_ns;
  previous_drops_for_health_ = drops;
  worst_scan_in_period_ = ScanVerdict::Good;
  resets_in_period_ = 0;
}

void StatusAggregator::tick(std::int64_t now_steady_ns, std::int64_t utime, tumble::status_t& out) {
  drain_scan_reports(std::numeric_limits<std::uint64_t>::max(), now_steady_ns);
  const PipelineCounters& c = counters_;
  evaluate_health(now_steady_ns, silent_s(c.last_imu_steady_ns.load(std::memory_order_relaxed), now_steady_ns),
                  silent_s(c.last_lidar_steady_ns.load(std::memory_order_relaxed), now_steady_ns),
                  c.fuser_initialised.load(std::memory_order_relaxed),
                  c.lidar_foreign_rate_hz.load(std::memory_order_relaxed));
  fill_message(now_steady_ns, utime, out);
}

void StatusAggregator::evaluate(const SensorTimeTick& tick) {
  const auto ns = [](double t_s) { return std::llround(t_s * 1e9); };
  const std::int64_t now_ns = ns(tick.t_s);
  if (!on_sensor_time_) {
    on_sensor_time_ = true;
    start_steady_ns_ = previous_steady_ns_ = state_since_steady_ns_ = now_ns;
  }
  drain_scan_reports(tick.scan_reports, now_ns);
  const auto sensor_silent_s = [&](double newest_s) { return newest_s >= 0.0 ? tick.t_s - newest_s : kNeverHeard_s; };
  // A reported scan was registered with the fuser's trajectory: the fuser is
  // initialised (its own flag changes at a moment no replay can reproduce).
  evaluate_health(now_ns, sensor_silent_s(tick.newest_imu_s), sensor_silent_s(tick.newest_lidar_s),
                  any_scan_reported_, tick.foreign_lidar_rate_hz);
}

void StatusAggregator::judge_final_scans(std::int64_t now_ns) {
  drain_scan_reports(std::numeric_limits<std::uint64_t>::max(), now_ns);
  evaluate_health(now_ns, 0.0, 0.0, any_scan_reported_ || counters_.fuser_initialised.load(std::memory_order_relaxed),
                  0.0);
}

void StatusAggregator::publish(std::int64_t now_ns, std::int64_t utime, tumble::status_t& out) {
  fill_message(now_ns, utime, out);
}

void StatusAggregator::fill_message(std::int64_t now_steady_ns, std::int64_t utime, tumble::status_t& out) {
  const double period_s = seconds(now_steady_ns - previous_steady_ns_);
  const PipelineCounters& c = counters_;
  const auto load = [](const std::atomic<std::int64_t>& a) { return a.load(std::memory_order_relaxed); };
  const std::uint64_t drops = sensor_drops();

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
  out.scans_cut_at_bound = load(c.scans_cut_at_bound);
  out.trajectory_lines_lost = load(c.trajectory_lines_lost);
  out.record_dropped = load(c.record_dropped);
  out.record_errors = load(c.record_errors);
  out.record_paused = c.record_paused.load(std::memory_order_relaxed);
  out.lidar_difop_ignored = load(c.lidar_difop_ignored);
  out.imu_duplicate_frames = load(c.imu_duplicate_frames);
  out.imu_out_of_order_frames = load(c.imu_out_of_order_frames);
  out.imu_rejected_samples = load(c.imu_rejected_samples);
  out.scans_registered = scans;
  out.scans_dropped = load(c.scans_dropped);
  out.scans_short_trajectory = load(c.scans_short_trajectory);
  out.resets = static_cast<std::int32_t>(load(c.resets));
  out.state_reason = state_reason_;
  out.scans_imu_bridged = load(c.scans_imu_bridged);
  out.scans_untrusted = load(c.scans_untrusted);
  out.scans_spin_rate_unmeasured = load(c.scans_spin_rate_unmeasured);
  out.scans_map_deferred = load(c.scans_map_deferred);
  out.scans_jumped = load(c.scans_jumped);
  out.scans_awaiting_rest = load(c.scans_awaiting_rest);
  out.scans_weakly_constrained = load(c.scans_weakly_constrained);
  out.expected_error_max_m = expected_error_max_m_;
  expected_error_max_m_ = 0.0f;

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
}

}  // namespace tumble::daemon
