// Builds tumble.status_t once per status period on the main thread: sensor
// rates, drops, ring fill, per-stage time per scan (median and max over the
// period), ICP statistics, saturation counts, clock estimates and the health
// state machine (health_state.hpp), with one log line per state change.
#pragma once

#include <spdlog/logger.h>
#include <spdlog/spdlog.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "daemon/config.hpp"
#include "daemon/health_state.hpp"
#include "daemon/period_stats.hpp"
#include "daemon/records.hpp"
#include "daemon/spsc_ring.hpp"
#include "daemon/status_counters.hpp"
#include "tumble/status_t.hpp"

namespace tumble::daemon {

struct NamedRing {
  std::string name;
  const RingCounters* ring;
  bool carries_sensor_data;  // its drops lose sensor data and degrade health
};

class StatusAggregator {
 public:
  // scan_reports: one RegistrationRecord per registered scan, drained at each tick.
  StatusAggregator(const HealthConfig& health, std::vector<std::string> stage_names, std::vector<NamedRing> rings,
                   const PipelineCounters& counters, SpscRing<RegistrationRecord>& scan_reports,
                   std::int64_t start_steady_ns, std::shared_ptr<spdlog::logger> logger = spdlog::default_logger());

  // now_steady_ns: monotonic clock; utime: host clock in microseconds (the message stamp).
  void tick(std::int64_t now_steady_ns, std::int64_t utime, tumble::status_t& out);

  // The input ended (a replay's files): the sensors falling silent is then
  // no fault, so later ticks keep the state (and log no change).
  void input_ended() { input_ended_ = true; }

  HealthState state() const { return state_; }
  // One line for systemd's STATUS=, from the last tick.
  const std::string& summary() const { return summary_; }

 private:
  static constexpr std::size_t kWindow = 64;  // scans per period kept for medians (10 Hz lidar: 10)

  bool is_good(const RegistrationRecord& r) const;
  void drain_scan_reports();

  HealthConfig health_;
  std::vector<std::string> stage_names_;
  std::vector<NamedRing> rings_;
  const PipelineCounters& counters_;
  SpscRing<RegistrationRecord>& scan_reports_;
  std::shared_ptr<spdlog::logger> logger_;

  std::int64_t start_steady_ns_;
  std::int64_t previous_steady_ns_;
  std::int64_t previous_lidar_packets_ = 0;
  std::int64_t previous_imu_samples_ = 0;
  std::int64_t previous_scans_ = 0;
  std::uint64_t previous_drops_ = 0;

  std::vector<PeriodStats<kWindow>> stage_ms_;  // sized once, at construction
  PeriodStats<kWindow> iterations_;
  PeriodStats<kWindow> inlier_ratio_;
  PeriodStats<kWindow> degeneracy_;
  int bad_scans_in_period_ = 0;
  int consecutive_good_scans_ = 0;

  bool input_ended_ = false;
  HealthState state_ = HealthState::WaitingForSensors;
  std::int64_t state_since_steady_ns_;
  std::string summary_;
};

}  // namespace tumble::daemon
