// Builds tumble.status_t once per status period on the main thread: sensor
// rates, drops, ring fill, per-stage time per scan (median and max over the
// period), ICP statistics, saturation counts, clock estimates and the health
// state machine (health_state.hpp), with one log line per state change.
//
// Two clocks. Live, tick() runs on the steady clock: sensors are fresh when
// their bytes arrived recently. A replay runs on the sensors' own time
// (SensorTimeTick, from the io thread through the registration thread):
// evaluate() at each health period of data time with exactly the scan reports
// pushed before it, and publish() at each status period, so a replay at any
// rate reports the states and warnings a live run would have, the same on
// every run.
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

  // Sensor time (replay): the health machine at tick.t_s, then the message.
  void evaluate(const SensorTimeTick& tick);
  void publish(std::int64_t now_ns, std::int64_t utime, tumble::status_t& out);

  // The input ended (a replay's files): the sensors falling silent is then
  // no fault, so later evaluations count them as fresh. They still judge the
  // scans registered since: a bad last scan is not left as tracking.
  void input_ended() { input_ended_ = true; }
  // After the input ended and the pipeline drained: the health machine once
  // more, over the scans it registered after the last evaluation (at now_ns:
  // the data time in a sensor-time replay, else the monotonic clock).
  void judge_final_scans(std::int64_t now_ns);

  HealthState state() const { return state_; }
  // One line for systemd's STATUS=, from the last tick.
  const std::string& summary() const { return summary_; }

 private:
  static constexpr std::size_t kWindow = 64;  // scans per period kept for medians (10 Hz lidar: 10)

  // until: the report count to reach (scan_reports_ pushes); now_ns: the health clock's time, which on
  // sensor time stamps the newest scan (live, its completion's steady time does).
  void drain_scan_reports(std::uint64_t until, std::int64_t now_ns);
  std::uint64_t sensor_drops() const;  // lost sensor data: dropped scans and sensor-ring drops
  // *_silent_s: since the sensor's newest data (infinity before any).
  void evaluate_health(std::int64_t now_ns, double imu_silent_s, double lidar_silent_s, bool fuser_initialised,
                       double foreign_lidar_rate_hz);
  void fill_message(std::int64_t now_ns, std::int64_t utime, tumble::status_t& out);

  HealthConfig health_;
  std::vector<std::string> stage_names_;
  std::vector<NamedRing> rings_;
  const PipelineCounters& counters_;
  SpscRing<RegistrationRecord>& scan_reports_;
  std::shared_ptr<spdlog::logger> logger_;

  // On the health clock: steady (live) or the sensors' (replay, set by the first evaluate()).
  std::int64_t start_steady_ns_;
  std::int64_t previous_steady_ns_;
  bool on_sensor_time_ = false;
  std::uint64_t reports_consumed_ = 0;
  std::int64_t previous_lidar_packets_ = 0;
  std::int64_t previous_imu_samples_ = 0;
  std::int64_t previous_scans_ = 0;

  std::vector<PeriodStats<kWindow>> stage_ms_;  // sized once, at construction
  PeriodStats<kWindow> iterations_;
  PeriodStats<kWindow> inlier_ratio_;
  PeriodStats<kWindow> degeneracy_;
  ScanVerdict worst_scan_in_period_ = ScanVerdict::Good;
  float expected_error_max_m_ = 0.0f;  // of the registered scans since the last message
  int consecutive_good_scans_ = 0;
  bool any_scan_reported_ = false;
  std::int64_t newest_scan_ns_ = 0;  // on the health clock, of the newest scan completed (valid once one was)
  int resets_in_period_ = 0;
  std::int32_t resets_seen_ = 0;
  TrackingLoss newest_reset_reason_ = TrackingLoss::None;
  std::int32_t new_map_at_resets_ = 0;  // resets count of the newest scan that started a map
  std::int32_t lost_at_resets_ = -1;    // resets count when the state became lost (-1: not lost)
  std::uint64_t previous_drops_for_health_ = 0;

  bool input_ended_ = false;
  HealthState state_ = HealthState::WaitingForSensors;
  std::int64_t state_since_steady_ns_;
  std::string state_reason_;
  std::string summary_;
};

}  // namespace tumble::daemon
