#include "daemon/health_state.hpp"

#include <gtest/gtest.h>

#include "tumble/status_t.hpp"

namespace tumble::daemon {
namespace {

using S = HealthState;

HealthInputs healthy() {
  HealthInputs in;
  in.imu_fresh = in.lidar_fresh = in.fuser_initialised = true;
  in.consecutive_good_scans = 10;
  return in;
}

HealthState next(S current, const HealthInputs& in, double time_in_state_s = 0.0) {
  return next_health_state(current, time_in_state_s, in, HealthLimits{3.0, 5}).state;
}

TEST(HealthState, ValuesMatchTheStatusMessage) {
  EXPECT_EQ(static_cast<int>(S::WaitingForSensors), static_cast<int>(tumble::status_t::STATE_WAITING_FOR_SENSORS));
  EXPECT_EQ(static_cast<int>(S::Initialising), static_cast<int>(tumble::status_t::STATE_INITIALISING));
  EXPECT_EQ(static_cast<int>(S::Tracking), static_cast<int>(tumble::status_t::STATE_TRACKING));
  EXPECT_EQ(static_cast<int>(S::Degraded), static_cast<int>(tumble::status_t::STATE_DEGRADED));
  EXPECT_EQ(static_cast<int>(S::Lost), static_cast<int>(tumble::status_t::STATE_LOST));
  EXPECT_EQ(to_string(S::WaitingForSensors), "waiting_for_sensors");
  EXPECT_EQ(to_string(S::Lost), "lost");
}

TEST(HealthState, WaitsUntilBothSensorsSendData) {
  HealthInputs in;
  EXPECT_EQ(next(S::WaitingForSensors, in), S::WaitingForSensors);
  in.imu_fresh = true;
  EXPECT_EQ(next(S::WaitingForSensors, in), S::WaitingForSensors);
  in.lidar_fresh = true;
  const HealthTransition t = next_health_state(S::WaitingForSensors, 0.0, in, {});
  EXPECT_EQ(t.state, S::Initialising);
  EXPECT_FALSE(t.reason.empty());
}

TEST(HealthState, InitialisingNeedsTheFuserAndAGoodScan) {
  HealthInputs in = healthy();
  in.fuser_initialised = false;
  EXPECT_EQ(next(S::Initialising, in), S::Initialising);
  in.fuser_initialised = true;
  in.consecutive_good_scans = 0;
  EXPECT_EQ(next(S::Initialising, in), S::Initialising);
  in.consecutive_good_scans = 1;
  EXPECT_EQ(next(S::Initialising, in), S::Tracking);
  in.lidar_fresh = false;
  EXPECT_EQ(next(S::Initialising, in), S::WaitingForSensors);
}

TEST(HealthState, TrackingDegradesOnStaleSensorsBadScansOrDrops) {
  EXPECT_EQ(next(S::Tracking, healthy()), S::Tracking);
  HealthInputs in = healthy();
  in.imu_fresh = false;
  const HealthTransition t = next_health_state(S::Tracking, 0.0, in, {});
  EXPECT_EQ(t.state, S::Degraded);
  EXPECT_EQ(t.reason, "no IMU data");
  in = healthy();
  in.worst_scan_in_period = ScanVerdict::PoorRegistration;
  const HealthTransition poor = next_health_state(S::Tracking, 0.0, in, {});
  EXPECT_EQ(poor.state, S::Degraded);
  EXPECT_EQ(poor.reason, "poor scan registration");
  in = healthy();
  in.data_dropped = true;
  EXPECT_EQ(next(S::Tracking, in), S::Degraded);
}

TEST(HealthState, AGyroClippedAboutTheSpinAxisDegradesWithThatReason) {
  HealthInputs in = healthy();
  in.worst_scan_in_period = ScanVerdict::SpinRateUnmeasured;
  const HealthTransition t = next_health_state(S::Tracking, 0.0, in, {});
  EXPECT_EQ(t.state, S::Degraded);
  EXPECT_EQ(t.reason,
            "gyro clipped about the lidar's spin axis: the spin is new, or the scan matched too little of the map to "
            "carry that rotation");
  in.consecutive_good_scans = 0;
  HealthTransition still = next_health_state(S::Degraded, 1.0, in, {});
  EXPECT_EQ(still.state, S::Degraded);
  EXPECT_EQ(still.reason, t.reason);
  in.worst_scan_in_period = ScanVerdict::Good;
  in.consecutive_good_scans = 5;
  EXPECT_EQ(next(S::Degraded, in), S::Tracking);
}

TEST(HealthState, AFirstMapWaitingForTheGyroStaysInitialisingAndSaysWhy) {
  HealthInputs in = healthy();
  in.consecutive_good_scans = 0;
  in.worst_scan_in_period = ScanVerdict::MapDeferred;
  const HealthTransition t = next_health_state(S::Initialising, 1.0, in, {});
  EXPECT_EQ(t.state, S::Initialising);
  EXPECT_EQ(t.reason,
            "no local map yet: the gyro is clipped, and the first map starts only from a scan it measured whole");
  in.consecutive_good_scans = 1;  // the map started, and its first scan counts
  EXPECT_EQ(next(S::Initialising, in), S::Tracking);
  // Lost, with a new map reset before any scan registered on it: the same reason.
  in.consecutive_good_scans = 0;
  const HealthTransition lost = next_health_state(S::Lost, 1.0, in, {});
  EXPECT_EQ(lost.state, S::Lost);
  EXPECT_EQ(lost.reason, t.reason);
}

TEST(HealthState, LostWaitingForRestSaysSoUntilANewMapStarts) {
  HealthInputs in = healthy();
  in.consecutive_good_scans = 0;
  in.worst_scan_in_period = ScanVerdict::AwaitingRest;
  const HealthTransition t = next_health_state(S::Lost, 1.0, in, {});
  EXPECT_EQ(t.state, S::Lost);
  EXPECT_EQ(t.reason, "tracking lost: waiting for the robot to be still to start again from zero velocity");
  in.worst_scan_in_period = ScanVerdict::Good;
  in.new_map_since_lost = true;
  EXPECT_EQ(next(S::Lost, in), S::Initialising);
}

TEST(HealthState, AJumpAndAScanWithoutTheImuDegradeWithTheirReasons) {
  HealthInputs in = healthy();
  in.worst_scan_in_period = ScanVerdict::Jumped;
  const HealthTransition jumped = next_health_state(S::Tracking, 1.0, in, {});
  EXPECT_EQ(jumped.state, S::Degraded);
  EXPECT_EQ(jumped.reason,
            "registration jumped from the IMU's prediction (registration.jump_sigmas): the prediction or the scan is "
            "wrong");
  in.worst_scan_in_period = ScanVerdict::ImuBridged;
  const HealthTransition bridged = next_health_state(S::Tracking, 1.0, in, {});
  EXPECT_EQ(bridged.state, S::Degraded);
  EXPECT_EQ(bridged.reason, "registered without IMU data: de-skewed and predicted from the registrations alone");
}

TEST(HealthState, AWeaklyConstrainedRegistrationDegradesWithThatReason) {
  HealthInputs in = healthy();
  in.worst_scan_in_period = ScanVerdict::WeaklyConstrained;
  const HealthTransition t = next_health_state(S::Tracking, 0.0, in, {});
  EXPECT_EQ(t.state, S::Degraded);
  EXPECT_EQ(t.reason,
            "registration weakly constrained: expected position error above daemon.health.max_expected_error_m");
  in.consecutive_good_scans = 0;
  EXPECT_EQ(next_health_state(S::Degraded, 1.0, in, {}).reason, t.reason);
  in.worst_scan_in_period = ScanVerdict::Good;
  in.consecutive_good_scans = 5;
  EXPECT_EQ(next(S::Degraded, in), S::Tracking);
}

TEST(HealthState, AnUnobservedDirectionDegradesWithThatReasonAndIsRestated) {
  HealthInputs in = healthy();
  in.worst_scan_in_period = ScanVerdict::DirectionUnobserved;
  const HealthTransition t = next_health_state(S::Tracking, 0.0, in, {});
  EXPECT_EQ(t.state, S::Degraded);
  EXPECT_EQ(t.reason.substr(0, 51), "direction unobserved: most recent scans leave one d");
  in.consecutive_good_scans = 0;
  EXPECT_EQ(next_health_state(S::Degraded, 1.0, in, {}).reason, t.reason);
  EXPECT_EQ(next_health_state(S::Degraded, 3.0, in, {}).state, S::Lost);
}

TEST(HealthState, ASecondLidarOnTheNetworkDegradesWithThatReasonUntilItStops) {
  HealthInputs in = healthy();
  in.second_lidar = true;
  const HealthTransition t = next_health_state(S::Tracking, 0.0, in, {});
  EXPECT_EQ(t.state, S::Degraded);
  EXPECT_NE(t.reason.find("a second host sends lidar traffic at a lidar's rate"), std::string_view::npos) << t.reason;
  // Good scans do not end it, nor does time make it lost: the pose is still the lidar's.
  const HealthTransition held = next_health_state(S::Degraded, 60.0, in, HealthLimits{3.0, 5});
  EXPECT_EQ(held.state, S::Degraded);
  EXPECT_EQ(held.reason, t.reason);
  EXPECT_TRUE(held.pose_good);  // the degraded-to-lost clock starts again
  in.consecutive_good_scans = 0;
  EXPECT_FALSE(next_health_state(S::Degraded, 1.0, in, HealthLimits{3.0, 5}).pose_good);
  in.consecutive_good_scans = 10;
  in.second_lidar = false;
  EXPECT_EQ(next(S::Degraded, in, 60.0), S::Tracking);
}

TEST(HealthState, LidarPointsThatCompleteNoScanAreAStaleLidarWithTheirOwnReason) {
  HealthInputs in = healthy();
  in.scan_silent_s = 0.4;
  EXPECT_EQ(next(S::Tracking, in), S::Tracking);
  in.scan_silent_s = 0.5;
  const HealthTransition t = next_health_state(S::Tracking, 0.0, in, {});
  EXPECT_EQ(t.state, S::Degraded);
  EXPECT_NE(t.reason.find("no scan completed"), std::string_view::npos) << t.reason;
  // Good scans from before the spell do not end it.
  EXPECT_EQ(next(S::Degraded, in, 1.0), S::Degraded);
  EXPECT_EQ(next(S::Degraded, in, 3.0), S::Lost);
  // A lidar without points is named as such, not as a lidar without scans.
  in.lidar_fresh = false;
  EXPECT_EQ(next_health_state(S::Tracking, 0.0, in, {}).reason, "no lidar data");
}

TEST(HealthState, DegradedRecoversAfterEnoughGoodScans) {
  HealthInputs in = healthy();
  in.consecutive_good_scans = 4;
  EXPECT_EQ(next(S::Degraded, in), S::Degraded);
  in.consecutive_good_scans = 5;
  EXPECT_EQ(next(S::Degraded, in), S::Tracking);
  in.data_dropped = true;
  EXPECT_EQ(next(S::Degraded, in), S::Degraded);
}

TEST(HealthState, DegradedTooLongIsLostUntilTheScansAreGoodAgain) {
  HealthInputs in = healthy();
  in.consecutive_good_scans = 0;
  EXPECT_EQ(next(S::Degraded, in, 2.9), S::Degraded);
  EXPECT_EQ(next(S::Degraded, in, 3.0), S::Lost);
  EXPECT_EQ(next(S::Lost, in, 100.0), S::Lost);
  in.consecutive_good_scans = 4;
  EXPECT_EQ(next(S::Lost, in), S::Lost);
  in.consecutive_good_scans = 5;  // the map was kept: tracked against again
  EXPECT_EQ(next(S::Lost, in), S::Tracking);
  in.imu_fresh = false;
  EXPECT_EQ(next(S::Lost, in), S::Lost);
  const HealthTransition still = next_health_state(S::Degraded, 1.0, in, {});
  EXPECT_EQ(still.state, S::Degraded);
  EXPECT_EQ(still.reason, "no IMU data");  // the reason changes, the state does not
}

TEST(HealthState, AResetIsLostWithItsReasonThenANewMapInitialises) {
  for (const S from : {S::Initialising, S::Tracking, S::Degraded}) {
    HealthInputs in = healthy();
    in.resets_in_period = 1;
    in.reset_reason = "registrations disagree with the IMU-propagated pose";
    const HealthTransition t = next_health_state(from, 0.0, in, {});
    EXPECT_EQ(t.state, S::Lost) << to_string(from);
    EXPECT_EQ(t.reason, in.reset_reason);
  }
  HealthInputs in = healthy();
  in.consecutive_good_scans = 0;
  EXPECT_EQ(next(S::Lost, in), S::Lost);
  // Lost already (degraded too long) when the map is given up: the reset's reason is said.
  in.resets_in_period = 1;
  in.reset_reason = "moving beyond fuser.max_speed_at_rest_m_s while the IMU was still";
  in.worst_scan_in_period = ScanVerdict::AwaitingRest;
  const HealthTransition again = next_health_state(S::Lost, 1.0, in, {});
  EXPECT_EQ(again.state, S::Lost);
  EXPECT_EQ(again.reason, in.reset_reason);
  in.resets_in_period = 0;
  in.worst_scan_in_period = ScanVerdict::Good;
  in.new_map_since_lost = true;
  EXPECT_EQ(next(S::Lost, in), S::Initialising);
  in.consecutive_good_scans = 1;
  EXPECT_EQ(next(S::Initialising, in), S::Tracking);
  in.resets_in_period = 1;  // waiting for sensors is not tracking: nothing to lose
  EXPECT_EQ(next(S::WaitingForSensors, in), S::Initialising);
}

TEST(HealthState, ALidarSilentTooLongIsLostWithThatReason) {
  const HealthLimits limits{3.0, 5, 1.0};
  HealthInputs in = healthy();
  in.lidar_fresh = false;
  in.lidar_silent_s = 0.9;
  EXPECT_EQ(next_health_state(S::Tracking, 0.0, in, limits).state, S::Degraded);
  EXPECT_EQ(next_health_state(S::Degraded, 0.7, in, limits).state, S::Degraded);
  in.lidar_silent_s = 1.0;
  for (const S from : {S::Tracking, S::Degraded}) {
    const HealthTransition t = next_health_state(from, 0.8, in, limits);
    EXPECT_EQ(t.state, S::Lost);
    EXPECT_EQ(t.reason, "no lidar data for too long: the pose is the IMU's alone");
  }
  EXPECT_EQ(next_health_state(S::Lost, 0.0, in, limits).state, S::Lost);
  EXPECT_EQ(next_health_state(S::Initialising, 0.0, in, limits).state, S::WaitingForSensors);
}

TEST(HealthState, ReinitialisingTheOdometryLeavesLost) {
  HealthInputs in = healthy();
  in.fuser_initialised = false;
  EXPECT_EQ(next(S::Lost, in), S::Initialising);
  EXPECT_EQ(next(S::Tracking, in), S::Initialising);
  in.imu_fresh = false;
  EXPECT_EQ(next(S::Degraded, in), S::WaitingForSensors);
}

}  // namespace
}  // namespace tumble::daemon
