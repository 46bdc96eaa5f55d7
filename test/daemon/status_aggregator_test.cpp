#include "daemon/status_aggregator.hpp"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>

#include <cmath>
#include <sstream>
#include <string>

#include "test/daemon/good_registration.hpp"

namespace tumble::daemon {
namespace {

constexpr std::int64_t kSecond = 1'000'000'000;

TEST(PeriodStats, MedianMinMaxOverThePeriod) {
  PeriodStats<8> stats;
  EXPECT_TRUE(std::isnan(stats.median()));
  EXPECT_TRUE(std::isnan(stats.max()));
  for (const float v : {5.0f, 1.0f, 3.0f}) stats.add(v);
  EXPECT_EQ(stats.median(), 3.0f);
  EXPECT_EQ(stats.min(), 1.0f);
  EXPECT_EQ(stats.max(), 5.0f);
  stats.add(4.0f);
  EXPECT_EQ(stats.median(), 3.5f);
  stats.reset();
  EXPECT_EQ(stats.count(), 0u);
  EXPECT_TRUE(std::isnan(stats.median()));
}

TEST(PeriodStats, MedianOfTheNewestWhenMoreThanTheWindowArrive) {
  PeriodStats<4> stats;
  for (int i = 0; i < 10; ++i) stats.add(static_cast<float>(i));  // newest four: 6 7 8 9
  EXPECT_EQ(stats.median(), 7.5f);
  EXPECT_EQ(stats.max(), 9.0f);  // max and min see everything
  EXPECT_EQ(stats.min(), 0.0f);
}

class StatusAggregatorTest : public ::testing::Test {
 protected:
  StatusAggregatorTest()
      : imu_ring_(10),
        out_ring_(10),
        reports_(16),
        sink_(std::make_shared<spdlog::sinks::ostream_sink_st>(log_)),
        logger_(std::make_shared<spdlog::logger>("test", sink_)),
        aggregator_(HealthConfig{}, {"deskew", "icp"}, {{"imu", &imu_ring_, true}, {"odometry_out", &out_ring_, false}},
                    counters_, reports_, 0, logger_) {
    logger_->set_pattern("%l %v");
  }

  void report_scan(bool good, float icp_ms) {
    RegistrationRecord r = registered_scan(good);
    r.iterations = 10;
    r.num_stages = 2;
    r.stage_ms = {1.0f, icp_ms};
    reports_.push(r);
  }

  // A registered scan that passes every test but, maybe, convergence.
  static RegistrationRecord registered_scan(bool converged) {
    RegistrationRecord r = good_registration();
    r.converged = converged;
    return r;
  }

  // A registered scan after `resets` resets of the local map (for `reason`), maybe the first of a new one.
  void report_map_scan(std::int32_t resets, TrackingLoss reason, bool map_initialised, bool good) {
    RegistrationRecord r = registered_scan(good);
    r.resets = resets;
    r.reset_reason = resets > 0 ? reason : TrackingLoss::None;
    r.map_initialised = map_initialised;
    reports_.push(r);
  }

  // The next health tick on sensor time, 0.1 s of data after the previous one.
  void evaluate_next_tick() {
    tick_s_ += 0.1;
    aggregator_.evaluate(SensorTimeTick{tick_s_, tick_s_ - 0.01, tick_s_ - 0.01, 0, reports_.pushed()});
  }

  // Sensors alive at 1 s and one good scan: tracking.
  void start_tracking() {
    counters_.fuser_initialised = true;
    sensors_alive(kSecond);
    report_scan(true, 1.0f);
    aggregator_.tick(kSecond, 0, status_);
    aggregator_.tick(kSecond, 0, status_);
    ASSERT_EQ(aggregator_.state(), HealthState::Tracking);
  }

  void sensors_alive(std::int64_t now_ns) {
    counters_.last_imu_steady_ns = now_ns;
    counters_.last_lidar_steady_ns = now_ns;
  }

  int log_lines() const {
    const std::string text = log_.str();
    return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  }

  PipelineCounters counters_;
  SpscRing<int> imu_ring_;
  SpscRing<int> out_ring_;
  SpscRing<RegistrationRecord> reports_;
  std::ostringstream log_;
  std::shared_ptr<spdlog::sinks::ostream_sink_st> sink_;
  std::shared_ptr<spdlog::logger> logger_;
  StatusAggregator aggregator_;
  tumble::status_t status_{};
  double tick_s_ = 10.0;
};

TEST_F(StatusAggregatorTest, RatesCountsAndRings) {
  counters_.imu_samples = 100;
  counters_.lidar_packets = 750;
  counters_.scans_registered = 10;
  counters_.imu_bad_frames = 2;
  counters_.scans_short_trajectory = 3;
  counters_.lidar_duplicate_packets = 11;
  counters_.lidar_late_packets = 12;
  counters_.lidar_late_packets_dropped = 13;
  counters_.scans_short_coverage = 14;
  counters_.imu_duplicate_frames = 15;
  counters_.imu_out_of_order_frames = 16;
  counters_.imu_rejected_samples = 17;
  counters_.scans_cut_at_bound = 18;
  counters_.lidar_difop_ignored = 19;
  counters_.gyro_saturated_samples[1] = 4;
  counters_.imu_clock.offset_s = 0.25;
  for (int i = 0; i < 5; ++i) imu_ring_.push(i);
  aggregator_.tick(2 * kSecond, 123, status_);
  EXPECT_EQ(status_.utime, 123);
  EXPECT_FLOAT_EQ(status_.imu_rate_hz, 50.0f);  // 100 samples in 2 s
  EXPECT_FLOAT_EQ(status_.lidar_packet_rate_hz, 375.0f);
  EXPECT_FLOAT_EQ(status_.scan_rate_hz, 5.0f);
  EXPECT_FLOAT_EQ(status_.uptime_s, 2.0f);
  EXPECT_EQ(status_.imu_bad_frames, 2);
  EXPECT_EQ(status_.scans_short_trajectory, 3);
  EXPECT_EQ(status_.lidar_duplicate_packets, 11);
  EXPECT_EQ(status_.lidar_late_packets, 12);
  EXPECT_EQ(status_.lidar_late_packets_dropped, 13);
  EXPECT_EQ(status_.scans_short_coverage, 14);
  EXPECT_EQ(status_.imu_duplicate_frames, 15);
  EXPECT_EQ(status_.imu_out_of_order_frames, 16);
  EXPECT_EQ(status_.imu_rejected_samples, 17);
  EXPECT_EQ(status_.scans_cut_at_bound, 18);
  EXPECT_EQ(status_.lidar_difop_ignored, 19);
  EXPECT_EQ(status_.gyro_saturated_samples[1], 4);
  EXPECT_EQ(status_.imu_clock_offset_s, 0.25);
  ASSERT_EQ(status_.num_rings, 2);
  EXPECT_EQ(status_.ring_name[0], "imu");
  EXPECT_FLOAT_EQ(status_.ring_fill[0], 0.5f);
  counters_.imu_samples = 200;
  aggregator_.tick(3 * kSecond, 124, status_);
  EXPECT_FLOAT_EQ(status_.imu_rate_hz, 100.0f);  // per period, not since start
}

TEST_F(StatusAggregatorTest, StageTimesAreMedianAndMaxOfThePeriod) {
  report_scan(true, 10.0f);
  report_scan(true, 30.0f);
  report_scan(true, 20.0f);
  aggregator_.tick(kSecond, 0, status_);
  ASSERT_EQ(status_.num_stages, 2);
  EXPECT_EQ(status_.stage_name[1], "icp");
  EXPECT_FLOAT_EQ(status_.stage_median_ms[1], 20.0f);
  EXPECT_FLOAT_EQ(status_.stage_max_ms[1], 30.0f);
  EXPECT_FLOAT_EQ(status_.icp_iterations_median, 10.0f);
  EXPECT_FLOAT_EQ(status_.inlier_ratio_median, 0.6f);
  aggregator_.tick(2 * kSecond, 0, status_);
  EXPECT_TRUE(std::isnan(status_.stage_median_ms[1]));  // nothing in this period
}

TEST_F(StatusAggregatorTest, StateMachineRunsOnTheCountersAndLogsOneLinePerChange) {
  aggregator_.tick(kSecond, 0, status_);
  EXPECT_EQ(aggregator_.state(), HealthState::WaitingForSensors);
  EXPECT_EQ(status_.state_name, "waiting_for_sensors");
  EXPECT_EQ(log_lines(), 0);

  sensors_alive(2 * kSecond);
  aggregator_.tick(2 * kSecond, 0, status_);
  EXPECT_EQ(aggregator_.state(), HealthState::Initialising);
  EXPECT_EQ(log_lines(), 1);

  counters_.fuser_initialised = true;
  report_scan(true, 5.0f);
  sensors_alive(3 * kSecond);
  aggregator_.tick(3 * kSecond, 0, status_);
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  EXPECT_EQ(status_.state, static_cast<int>(tumble::status_t::STATE_TRACKING));

  imu_ring_.push(1);
  for (int i = 0; i < 10; ++i) imu_ring_.push(i);  // overflow: sensor data dropped
  sensors_alive(4 * kSecond);
  aggregator_.tick(4 * kSecond, 0, status_);
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);

  for (int i = 0; i < 5; ++i) report_scan(true, 5.0f);
  sensors_alive(5 * kSecond);
  aggregator_.tick(5 * kSecond, 0, status_);
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);

  report_scan(false, 5.0f);  // not converged
  sensors_alive(6 * kSecond);
  aggregator_.tick(6 * kSecond, 0, status_);
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  counters_.last_lidar_steady_ns = 10 * kSecond;
  aggregator_.tick(10 * kSecond, 0, status_);  // the IMU silent, degraded for 4 s
  EXPECT_EQ(aggregator_.state(), HealthState::Lost);

  EXPECT_EQ(log_lines(), 6);  // one per change, no more
  EXPECT_NE(log_.str().find("warning state degraded -> lost: degraded for too long"), std::string::npos) << log_.str();
  EXPECT_NE(aggregator_.summary().find("lost"), std::string::npos);
}

TEST_F(StatusAggregatorTest, ASecondLidarDegradesLiveAndOnSensorTime) {
  ASSERT_NO_FATAL_FAILURE(start_tracking());
  counters_.lidar_foreign_rate_hz = HealthConfig{}.second_lidar_rate_hz - 1.0;  // many foreign datagrams, not a lidar
  report_scan(true, 1.0f);
  sensors_alive(2 * kSecond);
  aggregator_.tick(2 * kSecond, 0, status_);
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  counters_.lidar_foreign_rate_hz = 1125.0;
  report_scan(true, 1.0f);
  sensors_alive(3 * kSecond);
  aggregator_.tick(3 * kSecond, 0, status_);
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  EXPECT_NE(status_.state_reason.find("second host"), std::string::npos) << status_.state_reason;

  // A replay judges the rate the io thread saw at each tick, not the counter's latest value.
  counters_.lidar_foreign_rate_hz = 0.0;
  StatusAggregator replayed(HealthConfig{}, {}, {}, counters_, reports_, 0, logger_);
  for (double t_s = 1.0; t_s < 2.0; t_s += 0.1) {
    reports_.push(registered_scan(true));
    const bool foreign = t_s > 1.5;
    replayed.evaluate(SensorTimeTick{t_s, t_s - 0.01, t_s - 0.01, 0, reports_.pushed(), foreign ? 1125.0 : 0.0});
    EXPECT_EQ(replayed.state() == HealthState::Degraded, foreign) << t_s;
  }
  // Seconds of it with good scans, then one poor scan: degraded, not "degraded for too long".
  for (double t_s = 2.0; t_s < 6.0; t_s += 0.1) {
    reports_.push(registered_scan(true));
    replayed.evaluate(SensorTimeTick{t_s, t_s - 0.01, t_s - 0.01, 0, reports_.pushed(), 1125.0});
  }
  reports_.push(registered_scan(false));
  replayed.evaluate(SensorTimeTick{6.0, 5.99, 5.99, 0, reports_.pushed(), 1125.0});
  EXPECT_EQ(replayed.state(), HealthState::Degraded);
}

// The motor stalls with the lasers firing: points keep arriving, no scan completes.
TEST_F(StatusAggregatorTest, LidarPointsWithoutScansDegradeOnSensorTimeAndLive) {
  for (int i = 0; i < 6; ++i) {  // more good scans than good_scans_to_recover
    reports_.push(registered_scan(true));
    evaluate_next_tick();
  }
  ASSERT_EQ(aggregator_.state(), HealthState::Tracking);
  for (int i = 0; i < 4; ++i) evaluate_next_tick();  // 0.4 s of points, no scan
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  EXPECT_NE(log_.str().find("tracking -> degraded: no scan completed for daemon.health.scan_timeout_s"),
            std::string::npos)
      << log_.str();
  // The motor turns again: the good scans from before the stall do not count toward recovering.
  reports_.push(registered_scan(true));
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);

  // Live, a scan's own completion time counts, not the tick that drained it.
  StatusAggregator live(HealthConfig{}, {}, {}, counters_, reports_, 0, logger_);
  counters_.fuser_initialised = true;
  RegistrationRecord scan = registered_scan(true);
  scan.scan_complete_steady_ns = kSecond;
  reports_.push(scan);
  sensors_alive(kSecond);
  live.tick(kSecond, 0, status_);
  live.tick(kSecond, 0, status_);
  ASSERT_EQ(live.state(), HealthState::Tracking);
  scan.scan_complete_steady_ns = kSecond + kSecond / 10;
  reports_.push(scan);
  sensors_alive(2 * kSecond);
  live.tick(2 * kSecond, 0, status_);  // the newest scan completed 0.9 s ago
  EXPECT_EQ(live.state(), HealthState::Degraded);
}

TEST_F(StatusAggregatorTest, TheEndOfTheInputIsNotASensorFailure) {
  ASSERT_NO_FATAL_FAILURE(start_tracking());
  const int lines = log_lines();
  aggregator_.input_ended();
  aggregator_.tick(10 * kSecond, 0, status_);  // both sensors silent for 9 s
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  EXPECT_EQ(status_.state_name, "tracking");
  EXPECT_EQ(log_lines(), lines) << log_.str();
}

TEST_F(StatusAggregatorTest, ScansRegisteredAfterTheInputEndedAreStillJudged) {
  ASSERT_NO_FATAL_FAILURE(start_tracking());
  aggregator_.input_ended();
  aggregator_.tick(2 * kSecond, 0, status_);  // the sensors silent: the end, no fault
  ASSERT_EQ(aggregator_.state(), HealthState::Tracking);
  // The last scan, registered while the pipeline drained, was weakly constrained.
  RegistrationRecord last = registered_scan(true);
  last.expected_error_m = static_cast<float>(2 * HealthConfig{}.max_expected_error_m);
  reports_.push(last);
  aggregator_.judge_final_scans(3 * kSecond);
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  EXPECT_NE(log_.str().find("tracking -> degraded: registration weakly constrained"), std::string::npos) << log_.str();
}

TEST_F(StatusAggregatorTest, OutputRingDropsDoNotDegradeHealth) {
  ASSERT_NO_FATAL_FAILURE(start_tracking());
  for (int i = 0; i < 20; ++i) out_ring_.push(i);
  aggregator_.tick(kSecond, 0, status_);
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  EXPECT_EQ(status_.ring_drops[1], 10);
}


TEST_F(StatusAggregatorTest, OnSensorTimeTheTicksDecideNotTheClocks) {
  // Arrival stamps on the steady clock say nothing here: the ticks carry the data's own time.
  SensorTimeTick tick{100.0, 99.95, 99.95, 0, 0};
  aggregator_.evaluate(tick);
  EXPECT_EQ(aggregator_.state(), HealthState::Initialising);
  report_scan(true, 1.0f);
  report_scan(false, 1.0f);
  tick = {100.1, 100.05, 100.05, 0, 1};  // only the first report came before this tick
  aggregator_.evaluate(tick);
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  tick = {100.2, 100.15, 100.15, 0, 1};
  aggregator_.evaluate(tick);
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  tick = {100.3, 100.25, 100.25, 0, 2};  // the bad scan
  aggregator_.evaluate(tick);
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  for (int i = 0; i < 5; ++i) report_scan(true, 1.0f);
  tick = {100.4, 100.35, 100.35, 0, 7};
  aggregator_.evaluate(tick);
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  tick = {101.0, 100.45, 100.95, 0, 7};  // the IMU silent for 0.55 s of data time
  aggregator_.evaluate(tick);
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  aggregator_.publish(101'000'000'000, 101'000'000, status_);
  EXPECT_EQ(status_.state_reason, "no IMU data");
  EXPECT_FLOAT_EQ(status_.uptime_s, 1.0f);
  EXPECT_NE(log_.str().find("warning state tracking -> degraded: no IMU data"), std::string::npos) << log_.str();
}

TEST_F(StatusAggregatorTest, ClippedSpinScansDegradeWhileNewOrMatchingLittleAndTheStatusCarriesTheirCount) {
  std::int32_t clipped_in_row = 0;
  const auto scan = [&](bool spin_rate_unmeasured, float matched_ratio = 0.6f) {
    RegistrationRecord r = registered_scan(true);
    r.spin_rate_unmeasured = spin_rate_unmeasured;
    clipped_in_row = spin_rate_unmeasured ? clipped_in_row + 1 : 0;
    r.spin_clipped_scans_in_row = clipped_in_row;
    r.matched_ratio = matched_ratio;
    reports_.push(r);
  };
  scan(false);
  evaluate_next_tick();
  evaluate_next_tick();
  ASSERT_EQ(aggregator_.state(), HealthState::Tracking);
  scan(true);  // a new spin: the fuser's rate for it still lags
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  EXPECT_NE(log_.str().find("tracking -> degraded: gyro clipped about the lidar's spin axis: the spin is new"),
            std::string::npos)
      << log_.str();
  for (int i = 0; i < 7; ++i) scan(true);  // settled, matched as a measured scan does: good, and recovered
  evaluate_next_tick();
  ASSERT_EQ(aggregator_.state(), HealthState::Tracking);
  scan(true, 0.27f);  // converged, and good by every other test: matched enough for a measured spin, not a clipped one
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  const std::string transition = "tracking -> degraded: gyro clipped about the lidar's spin axis";
  const std::string log = log_.str();
  const std::size_t first = log.find(transition);
  ASSERT_NE(first, std::string::npos) << log;
  EXPECT_NE(log.find(transition, first + 1), std::string::npos) << log;  // the second time, for the match
  for (int i = 0; i < 4; ++i) scan(false);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);  // 4 good scans: one short of recovering
  scan(false);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  counters_.scans_spin_rate_unmeasured = 1;
  aggregator_.publish(0, 0, status_);
  EXPECT_EQ(status_.scans_spin_rate_unmeasured, 1);
}

TEST_F(StatusAggregatorTest, AFirstMapWaitingForTheGyroKeepsInitialisingSaysWhyAndIsCounted) {
  counters_.fuser_initialised = true;
  evaluate_next_tick();
  ASSERT_EQ(aggregator_.state(), HealthState::Initialising);
  RegistrationRecord deferred;
  deferred.map_deferred = true;
  reports_.push(deferred);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Initialising);
  EXPECT_NE(log_.str().find("warning state initialising: no local map yet: the gyro is clipped"), std::string::npos)
      << log_.str();
  report_map_scan(0, TrackingLoss::None, true, true);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  counters_.scans_map_deferred = 3;
  aggregator_.publish(0, 0, status_);
  EXPECT_EQ(status_.scans_map_deferred, 3);
}

TEST_F(StatusAggregatorTest, WeaklyConstrainedScansDegradeAndTheLargestExpectedErrorIsReported) {
  const double limit_m = HealthConfig{}.max_expected_error_m;
  const auto scan = [this](double expected_error_m) {
    RegistrationRecord r = registered_scan(true);
    r.expected_error_m = static_cast<float>(expected_error_m);
    reports_.push(r);
  };
  scan(0.01);
  evaluate_next_tick();
  evaluate_next_tick();
  ASSERT_EQ(aggregator_.state(), HealthState::Tracking);
  scan(limit_m * 0.9);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  scan(limit_m * 1.5);
  reports_.push(registered_scan(false));  // a poor registration after it in the period: the more specific reason wins
  scan(0.01);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  EXPECT_NE(log_.str().find("tracking -> degraded: registration weakly constrained"), std::string::npos) << log_.str();
  aggregator_.publish(0, 0, status_);
  EXPECT_FLOAT_EQ(status_.expected_error_max_m, static_cast<float>(limit_m * 1.5));
  aggregator_.publish(0, 0, status_);
  EXPECT_EQ(status_.expected_error_max_m, 0.0f);  // per period
  for (int i = 0; i < 5; ++i) scan(0.01);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  counters_.scans_weakly_constrained = 1;
  aggregator_.publish(0, 0, status_);
  EXPECT_EQ(status_.scans_weakly_constrained, 1);
}

TEST_F(StatusAggregatorTest, AnUnobservedDirectionDegradesWithItsReasonUntilTheScansPinEveryDirection) {
  const auto scan = [this](bool unobserved) {
    RegistrationRecord r = registered_scan(true);
    r.direction_unobserved = unobserved;
    r.expected_error_m = 0.01f;  // within the threshold: the direction alone degrades
    reports_.push(r);
  };
  scan(false);
  evaluate_next_tick();
  evaluate_next_tick();
  ASSERT_EQ(aggregator_.state(), HealthState::Tracking);
  scan(true);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  EXPECT_NE(log_.str().find("tracking -> degraded: direction unobserved"), std::string::npos) << log_.str();
  // Scans that would pass every other check do not recover it while the direction stays unobserved.
  for (int i = 0; i < 8; ++i) scan(true);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  for (int i = 0; i < 5; ++i) scan(false);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
}

TEST_F(StatusAggregatorTest, AResetIsLostThenTheNewMapInitialisesThenTracks) {
  const auto scan = [this](std::int32_t resets, bool map_initialised, bool good) {
    report_map_scan(resets, TrackingLoss::DisagreesWithImu, map_initialised, good);
  };
  scan(0, true, false);
  scan(0, false, true);
  evaluate_next_tick();
  evaluate_next_tick();
  ASSERT_EQ(aggregator_.state(), HealthState::Tracking);
  scan(0, false, false);
  scan(1, false, false);  // the registration gave up its map
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Lost);
  EXPECT_NE(log_.str().find("tracking -> lost: registrations disagree with the IMU-propagated pose"),
            std::string::npos)
      << log_.str();
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Lost);  // no new map yet
  scan(1, true, false);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Initialising);
  scan(1, false, true);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
  counters_.resets = 1;
  aggregator_.publish(0, 0, status_);
  EXPECT_EQ(status_.resets, 1);
}

// After a lidar gap the registration checks scans against the IMU-propagated
// pose; one it does not trust may have converged well, and is still no
// reason to report tracking (cage3 of the fault table did, for 0.1 s, before
// three such scans gave up the map).
TEST_F(StatusAggregatorTest, AnUntrustedRegistrationIsNotAGoodScan) {
  reports_.push(registered_scan(true));
  evaluate_next_tick();
  evaluate_next_tick();
  ASSERT_EQ(aggregator_.state(), HealthState::Tracking);
  RegistrationRecord untrusted = registered_scan(true);
  untrusted.registered = false;
  untrusted.untrusted = true;
  for (int i = 0; i < 5; ++i) reports_.push(untrusted);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  for (int i = 0; i < 5; ++i) reports_.push(untrusted);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);  // five converged, none trusted: not recovered
}

TEST_F(StatusAggregatorTest, AScanThatFoundTooFewMapPointsIsNotGood) {
  reports_.push(registered_scan(true));
  evaluate_next_tick();
  evaluate_next_tick();
  ASSERT_EQ(aggregator_.state(), HealthState::Tracking);
  RegistrationRecord little_overlap = registered_scan(true);
  little_overlap.matched_ratio = 0.24f;  // under daemon.health.min_matched_ratio (0.25)
  reports_.push(little_overlap);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);
  for (int i = 0; i < 5; ++i) reports_.push(registered_scan(true));
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
}

// The registration resets only with the first scan after the silence, so
// lost comes first and the reset follows while lost.
TEST_F(StatusAggregatorTest, ALidarSilentTooLongIsLostThenTheNewMapInitialisesThenTracks) {
  const auto scan = [this](std::int32_t resets, bool map_initialised, bool good) {
    report_map_scan(resets, TrackingLoss::LidarSilent, map_initialised, good);
  };
  const auto tick = [this](double newest_lidar_s) {
    tick_s_ += 0.1;
    aggregator_.evaluate(SensorTimeTick{tick_s_, tick_s_ - 0.01, newest_lidar_s, 0, reports_.pushed()});
  };
  scan(0, true, false);
  for (int i = 0; i < 5; ++i) scan(0, false, true);
  evaluate_next_tick();
  evaluate_next_tick();
  ASSERT_EQ(aggregator_.state(), HealthState::Tracking);
  const double silent_from_s = tick_s_;
  for (int i = 0; i < 9; ++i) tick(silent_from_s);
  EXPECT_EQ(aggregator_.state(), HealthState::Degraded);  // 0.9 s
  tick(silent_from_s);
  tick(silent_from_s);
  EXPECT_EQ(aggregator_.state(), HealthState::Lost);  // 1.1 s
  EXPECT_NE(log_.str().find("degraded -> lost: no lidar data for too long"), std::string::npos) << log_.str();
  for (int i = 0; i < 20; ++i) tick(silent_from_s);
  EXPECT_EQ(aggregator_.state(), HealthState::Lost);
  evaluate_next_tick();  // lidar data again, no scan yet: the good scans before the silence do not count
  EXPECT_EQ(aggregator_.state(), HealthState::Lost);
  scan(1, true, false);  // the first scan after the silence starts a new map
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Initialising);
  scan(1, false, true);
  evaluate_next_tick();
  EXPECT_EQ(aggregator_.state(), HealthState::Tracking);
}

}  // namespace
}  // namespace tumble::daemon
