// The registration stage's scan assembly as the daemon runs it: a scan that
// covers too little of a turn is not registered, and each packet fault is
// counted for status_t and named in the log; the gyro's clipping flags a
// scan, and keeps the first map from starting. The fuser stage restarts at
// rest after a loss of track its velocity may have caused.
#include "daemon/core_stages.hpp"

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <limits>
#include <memory>
#include <set>
#include <sstream>
#include <vector>

#include "daemon/driver_params.hpp"
#include "drivers/rs16/decoder.hpp"
#include "test/daemon/captured_log.hpp"
#include "test/drivers/rs16/packet_stream.hpp"

namespace tumble::daemon {
namespace {

TEST(CoreRegistrationStage, SkipsShortScansAndNamesPacketFaultsInTheLog) {
  const CapturedLog log;
  CoreRegistrationStage stage(odometry_params(DaemonConfig{}), scan_assembler_config(LidarConfig{}));
  rs16::Decoder decoder;
  rs16::DecoderStats decoder_stats;
  rs16::test::StreamSpec spec;
  spec.start_azimuth_deg = 200.0;  // the first scan covers 160 deg
  int held = 0;
  PointBlock block;
  const auto feed = [&](std::int64_t i) {
    ASSERT_TRUE(decoder.decode_msop(rs16::encode_msop(rs16::test::stream_packet(spec, i)), 0.0, block, decoder_stats));
    if (stage.add_points(block)) {
      ++held;
      stage.discard_held_scan();
    }
  };
  std::set<std::int64_t> lost;
  for (std::int64_t i = 150; i < 180; ++i) lost.insert(i);  // 40 % of the third revolution
  for (std::int64_t i = 0; i < 250; ++i) {
    if (lost.contains(i)) continue;
    if (i == 100) {  // swapped with its neighbour
      feed(101);
      feed(100);
      ++i;
      continue;
    }
    feed(i);
    if (i == 60) feed(60);  // duplicates: at once and a packet later
    if (i == 90) feed(89);
  }
  // Scans: 0 (short, the start), 1 (whole), 2 (short: lost packets).
  EXPECT_EQ(held, 1);
  PipelineCounters counters;
  stage.report(counters);
  EXPECT_EQ(counters.scans_short_coverage.load(), 2);
  EXPECT_EQ(counters.lidar_duplicate_packets.load(), 2);
  EXPECT_EQ(counters.lidar_late_packets.load(), 1);
  EXPECT_EQ(counters.lidar_late_packets_dropped.load(), 0);
  EXPECT_EQ(counters.lidar_missing_packets.load(), 30);
  const std::string text = log.text();
  EXPECT_NE(text.find("warning lidar: duplicated MSOP packet dropped; 1 so far"), std::string::npos) << text;
  EXPECT_NE(text.find("warning lidar: MSOP packet out of order: put into its scan; 1 so far"), std::string::npos)
      << text;
  EXPECT_NE(text.find("warning lidar: scan 2 lost 30 MSOP packets; 30 so far"), std::string::npos) << text;
  EXPECT_EQ(text.find("scan 1 lost"), std::string::npos) << "the late packet was not lost:\n" << text;
  EXPECT_NE(text.find("warning lidar: scan 2 covers 60 % of a turn (lidar.min_scan_coverage 90 %): skipped; 2 so far"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("scan 0 covers"), std::string::npos) << "the first scan is partial by nature:\n" << text;
}

// The motor stalls for 2 s with the lasers firing, then turns again.
TEST(CoreRegistrationStage, SkipsScansCutAtTheBoundAndNamesThemInTheLog) {
  const CapturedLog log;
  CoreRegistrationStage stage(odometry_params(DaemonConfig{}), scan_assembler_config(LidarConfig{}));
  rs16::Decoder decoder;
  rs16::DecoderStats decoder_stats;
  const rs16::test::StreamSpec spec;
  PointBlock block;
  int held_in_stall = 0, held_after = 0;
  for (std::int64_t i = 0; i < 3000; ++i) {  // 75 packets a turn
    rs16::MsopPacketData data = rs16::test::stream_packet(spec, i);
    const bool stalled = i >= 300 && i < 1800;
    if (stalled)
      for (auto& b : data.blocks) b.azimuth_deg = 45.0;
    ASSERT_TRUE(decoder.decode_msop(rs16::encode_msop(data), 0.0, block, decoder_stats));
    if (stage.add_points(block)) {
      held_in_stall += stalled && i > 300;  // the first stalled packet may end the last turning scan
      held_after += i >= 1800;
      stage.discard_held_scan();
    }
  }
  PipelineCounters counters;
  stage.report(counters);
  EXPECT_GE(counters.scans_cut_at_bound.load(), 6);
  EXPECT_EQ(held_in_stall, 0);
  EXPECT_GE(held_after, 14);  // the motor turns again: whole scans again
  const std::string text = log.text();
  EXPECT_NE(text.find("ran 1.5 revolutions at 300 rpm"), std::string::npos) << text;
  EXPECT_NE(text.find("without passing the split azimuth (motor stalled?): cut and skipped; 1 so far"),
            std::string::npos)
      << text;
}

// A still trajectory over the scan, the gyro clipped about lidar axes
// `clipped_axes` (bits) at one sample in its middle; the fuser's velocity
// along x is `speed_m_s` (a still pose: the fuser's velocity gone wrong), and
// it has found `runaways_at_rest` still windows with a speed over the limit.
std::vector<TrajectoryRecord> still_trajectory(RegistrationStage::TimeSpan span, std::uint8_t clipped_axes,
                                               double speed_m_s = 0.0, std::uint32_t runaways_at_rest = 0) {
  std::vector<TrajectoryRecord> trajectory;
  for (double t = span.start_s - 0.05; t < span.end_s + 0.05; t += 0.01) {
    TrajectoryRecord r;
    r.t_s = t;
    r.v_w_m_s[0] = speed_m_s;
    r.runaways_at_rest = runaways_at_rest;
    trajectory.push_back(r);
  }
  trajectory[trajectory.size() / 2].gyro_saturated_axes = clipped_axes;
  return trajectory;
}

// Registers one scan per entry of `clipped` (the gyro's clipped lidar axes
// over it, on a still trajectory) and returns their records, with the lidar
// silent for 1.3 s (a reset: lidar_silent_to_lost_s is 1 s) before scan
// number `silent_before`, and the fuser's speed over scan i `speeds_m_s[i]`
// and its runaways at rest so far `runaways_at_rest[i]` (0 where absent).
std::vector<RegistrationRecord> take_scans(const std::vector<std::uint8_t>& clipped,
                                           std::size_t silent_before = std::numeric_limits<std::size_t>::max(),
                                           const OdometryParams& params = odometry_params(DaemonConfig{}),
                                           const std::vector<double>& speeds_m_s = {},
                                           const std::vector<std::uint32_t>& runaways_at_rest = {}) {
  CoreRegistrationStage stage(params, scan_assembler_config(LidarConfig{}));
  rs16::Decoder decoder;
  rs16::DecoderStats decoder_stats;
  const rs16::test::StreamSpec spec;
  PointBlock block;
  std::vector<RegistrationRecord> taken;
  bool silent_yet = false;
  for (std::int64_t i = 0; i < 2000 && taken.size() < clipped.size(); ++i) {
    if (taken.size() == silent_before && !silent_yet) {
      i += 1000;  // 1.33 ms a packet
      silent_yet = true;
    }
    EXPECT_TRUE(decoder.decode_msop(rs16::encode_msop(rs16::test::stream_packet(spec, i)), 0.0, block, decoder_stats));
    if (!stage.add_points(block)) continue;
    const std::size_t n = taken.size();
    taken.emplace_back();
    stage.register_held_scan(
        still_trajectory(stage.held_scan_span(), clipped[n], n < speeds_m_s.size() ? speeds_m_s[n] : 0.0,
                         n < runaways_at_rest.size() ? runaways_at_rest[n] : 0),
        taken.back(), nullptr);
  }
  return taken;
}

TEST(CoreRegistrationStage, FlagsScansWithTheGyroClippedAboutTheSpinAxis) {
  // The flag comes from the trajectory alone: every scan is left unregistered
  // (too few points, and then no map to start: the first map waits for a
  // scan the gyro measured whole), which keeps the test quick under the
  // sanitizers.
  OdometryParams params = odometry_params(DaemonConfig{});
  params.min_scan_points = std::numeric_limits<std::size_t>::max();
  // Clipped about lidar x, then z (the RS-16 spins about z), then x and z.
  std::vector<bool> flagged;
  for (const RegistrationRecord& r : take_scans({0b001, 0b100, 0b101}, std::numeric_limits<std::size_t>::max(), params))
    flagged.push_back(r.spin_rate_unmeasured);
  EXPECT_EQ(flagged, (std::vector<bool>{false, true, true}));
}

// How the stage took each scan.
struct Taken {
  bool deferred, map_initialised, registered;
  bool operator==(const Taken&) const = default;
};

std::vector<Taken> taken(const std::vector<RegistrationRecord>& records) {
  std::vector<Taken> out;
  for (const RegistrationRecord& r : records) out.push_back({r.map_deferred, r.map_initialised, r.registered});
  return out;
}

constexpr std::uint8_t kWhole = 0b000;
constexpr std::uint8_t kClippedAboutX = 0b001;  // the cage rolling

TEST(CoreRegistrationStage, TheFirstMapWaitsForAScanTheGyroMeasuredWhole) {
  // The clipped scan after the map exists is registered against it as usual.
  EXPECT_EQ(taken(take_scans({kClippedAboutX, kWhole, kClippedAboutX})),
            (std::vector<Taken>{{true, false, false}, {false, true, true}, {false, false, true}}));
}

TEST(CoreRegistrationStage, AfterAScanRegisteredOnAMapANewMapStartsEvenWithTheGyroClipped) {
  // The lidar silent, then a new map: the fuser has the last registrations' rate.
  EXPECT_EQ(taken(take_scans({kWhole, kWhole, kClippedAboutX}, 2)),
            (std::vector<Taken>{{false, true, true}, {false, false, true}, {false, true, true}}));
  // Reset before any scan registered on the first map: still no rate to take.
  EXPECT_EQ(taken(take_scans({kWhole, kClippedAboutX}, 1)),
            (std::vector<Taken>{{false, true, true}, {true, false, false}}));
}

TEST(CoreRegistrationStage, CountsAClippedSpinsScansInARowAndStartsAgainAfterALidarSilence) {
  constexpr std::uint8_t kClippedAboutZ = 0b100;  // the RS-16's spin axis
  std::vector<std::int32_t> in_row;
  for (const RegistrationRecord& r :
       take_scans({kWhole, kClippedAboutZ, kClippedAboutZ, kClippedAboutZ, kClippedAboutZ, kWhole, kClippedAboutZ}, 3))
    in_row.push_back(r.spin_clipped_scans_in_row);
  // The fourth scan comes after the silence, on a new map: the fuser's rate is a second old.
  EXPECT_EQ(in_row, (std::vector<std::int32_t>{0, 1, 2, 1, 2, 0, 1}));
}

// Of four scans, the second kept its map and the third lost it for `reason`
// and waits for the robot to rest.
void expect_third_scan_lost_awaiting_rest(const std::vector<RegistrationRecord>& records, TrackingLoss reason) {
  EXPECT_FALSE(records[1].awaiting_rest);
  EXPECT_EQ(records[1].resets, 0);
  EXPECT_TRUE(records[2].awaiting_rest);
  EXPECT_EQ(records[2].resets, 1);
  EXPECT_EQ(records[2].reset_reason, reason);
}

TEST(CoreRegistrationStage, AFusedSpeedNoRobotReachesLosesTrackAndWaitsForTheNextRest) {
  const DaemonConfig config;
  const double too_fast_m_s = config.fuser.max_speed_m_s + 0.5;
  const std::vector<RegistrationRecord> records =
      take_scans({kWhole, kWhole, kWhole, kWhole}, std::numeric_limits<std::size_t>::max(), odometry_params(config),
                 {0.0, config.fuser.max_speed_m_s - 0.5, too_fast_m_s, 0.0});
  ASSERT_EQ(records.size(), 4u);
  expect_third_scan_lost_awaiting_rest(records, TrackingLoss::TooFast);
  // No rest has come since (the trajectory's rest count stays 0): no new map.
  EXPECT_TRUE(records[3].awaiting_rest);
  EXPECT_FALSE(records[3].registered);
}

TEST(CoreRegistrationStage, AFuserFoundMovingAtRestLosesTrackAndWaitsForTheNextRest) {
  const std::vector<RegistrationRecord> records = take_scans({kWhole, kWhole, kWhole, kWhole},
                                                             std::numeric_limits<std::size_t>::max(),
                                                             odometry_params(DaemonConfig{}), {}, {0, 0, 1, 1});
  ASSERT_EQ(records.size(), 4u);
  expect_third_scan_lost_awaiting_rest(records, TrackingLoss::MovingAtRest);
  // The same runaway is not a second loss.
  EXPECT_EQ(records[3].resets, 1);
  EXPECT_TRUE(records[3].awaiting_rest);
}

TEST(CoreRegistrationStage, TheSpeedLimitDoesNotJudgeAMapStartedAfterALidarSilence) {
  // The IMU alone carried the velocity through the silence; the new map's
  // registrations are what measure it.
  const DaemonConfig config;
  const double too_fast_m_s = config.fuser.max_speed_m_s + 0.5;
  const std::vector<RegistrationRecord> records = take_scans(
      {kWhole, kWhole, kWhole, kWhole}, 2, odometry_params(config), {0.0, 0.0, too_fast_m_s, too_fast_m_s});
  ASSERT_EQ(records.size(), 4u);
  EXPECT_EQ(records[3].reset_reason, TrackingLoss::LidarSilent);
  EXPECT_EQ(records[3].resets, 1);
  EXPECT_FALSE(records[3].awaiting_rest);
  EXPECT_TRUE(records[3].registered);
}

// An IMU sample at t_s: still, or turning at 1 rad/s about z (not still).
ImuSample imu_sample(double t_s, bool turning) {
  ImuSample sample;
  sample.t_s = t_s;
  sample.accel_m_s2 = Eigen::Vector3d(0.0, 0.0, 9.80665);
  if (turning) sample.gyro_rad_s = Eigen::Vector3d(0.0, 0.0, 1.0);
  return sample;
}

// The fuser stage's newest record after feeding samples from t_from_s to t_to_s.
TrajectoryRecord feed_fuser(CoreFuserStage& fuser, double t_from_s, double t_to_s, bool turning) {
  TrajectoryRecord newest;
  for (double t = t_from_s; t <= t_to_s + 1e-9; t += 0.01) fuser.add_imu(imu_sample(t, turning), newest);
  return newest;
}

TEST(CoreFuserStage, ALossByUnregisteredScansRestartsTheFuserAtTheNextRest) {
  CoreFuserStage fuser(odometry_params(DaemonConfig{}));
  feed_fuser(fuser, 0.0, 1.2, false);  // initialised
  EXPECT_FALSE(feed_fuser(fuser, 1.21, 2.0, true).awaiting_rest);
  RegistrationRecord lost;
  lost.t_s = 1.9;
  lost.resets = 1;
  lost.reset_reason = TrackingLoss::NotRegistered;
  fuser.add_correction(lost, [](const TrajectoryRecord&) {});
  const TrajectoryRecord waiting = feed_fuser(fuser, 2.01, 3.0, true);
  EXPECT_TRUE(waiting.awaiting_rest);
  EXPECT_EQ(waiting.rests, 0u);
  const TrajectoryRecord rested = feed_fuser(fuser, 3.01, 3.7, false);  // still for longer than fuser.rest_static_s
  EXPECT_FALSE(rested.awaiting_rest);
  EXPECT_EQ(rested.rests, 1u);
  EXPECT_EQ(rested.resets, 1);
}

// Whether the fuser waits for rest after the registration stage gave up its map for `reason`.
bool waits_for_rest_after(TrackingLoss reason) {
  CoreFuserStage fuser(odometry_params(DaemonConfig{}));
  feed_fuser(fuser, 0.0, 1.2, false);
  RegistrationRecord lost;
  lost.t_s = 1.1;
  lost.resets = 1;
  lost.reset_reason = reason;
  fuser.add_correction(lost, [](const TrajectoryRecord&) {});
  return feed_fuser(fuser, 1.21, 2.0, true).awaiting_rest;
}

TEST(CoreFuserStage, ARunawayRestartsTheFuserAtTheNextRest) {
  EXPECT_TRUE(waits_for_rest_after(TrackingLoss::TooFast));
  EXPECT_TRUE(waits_for_rest_after(TrackingLoss::MovingAtRest));
}

TEST(CoreFuserStage, ALossOfTheLidarKeepsTheVelocity) {
  // The IMU carried the pose: its velocity is not the suspect.
  EXPECT_FALSE(waits_for_rest_after(TrackingLoss::LidarSilent));
}

}  // namespace
}  // namespace tumble::daemon
