#include "daemon/lcm_publisher.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "daemon/lcm_messages.hpp"
#include "test/daemon/alloc_counter.hpp"

namespace tumble::daemon {
namespace {

// Collects decoded messages of one type from an in-process (memq://) LCM.
template <class Message>
struct Inbox {
  std::vector<Message> messages;
  std::vector<std::string> channels;
  void handle(const lcm::ReceiveBuffer*, const std::string& channel, const Message* message) {
    messages.push_back(*message);
    channels.push_back(channel);
  }
};

class LcmPublisherTest : public ::testing::Test {
 protected:
  LcmPublisherTest() : lcm_("memq://"), odometry_(8), registrations_(8) {}

  void SetUp() override {
    ASSERT_TRUE(lcm_.good());
    lcm_.subscribe("TEST_ODOM", &Inbox<tumble::odometry_t>::handle, &odometry_inbox_);
    lcm_.subscribe("TEST_POSE", &Inbox<tumble::registration_t>::handle, &pose_inbox_);
    lcm_.subscribe("TEST_STATUS", &Inbox<tumble::status_t>::handle, &status_inbox_);
    lcm_.subscribe("TEST_SCAN", &Inbox<tumble::scan_t>::handle, &scan_inbox_);
    lcm_.subscribe("TEST_MAP", &Inbox<tumble::map_t>::handle, &map_inbox_);
  }

  // Delivers everything memq queued, without waiting.
  void deliver() {
    while (lcm_.handleTimeout(0) > 0) {
    }
  }

  PublisherInputs inputs() { return {&odometry_, &registrations_, &status_, &scans_, &maps_}; }

  lcm::LCM lcm_;
  Wakeup wakeup_;
  SpscRing<TrajectoryRecord> odometry_;
  SpscRing<RegistrationRecord> registrations_;
  Mailbox<tumble::status_t> status_;
  Mailbox<tumble::scan_t> scans_;
  Mailbox<tumble::map_t> maps_;
  Inbox<tumble::odometry_t> odometry_inbox_;
  Inbox<tumble::registration_t> pose_inbox_;
  Inbox<tumble::status_t> status_inbox_;
  Inbox<tumble::scan_t> scan_inbox_;
  Inbox<tumble::map_t> map_inbox_;
};

TEST(LcmChannels, PrefixNamesEveryChannel) {
  const LcmChannels c = LcmChannels::with_prefix("ROBOT1_");
  EXPECT_EQ(c.odometry, "ROBOT1_ODOM");
  EXPECT_EQ(c.pose, "ROBOT1_POSE");
  EXPECT_EQ(c.status, "ROBOT1_STATUS");
  EXPECT_EQ(c.scan, "ROBOT1_SCAN");
  EXPECT_EQ(c.map, "ROBOT1_MAP");
}

TEST_F(LcmPublisherTest, OdometryDecodesWithItsContent) {
  LcmPublisher publisher(lcm_, LcmChannels::with_prefix("TEST_"), inputs(), {}, wakeup_);
  TrajectoryRecord sample;
  sample.t_s = 1700000000.25;
  sample.p_w_m = {1, 2, 3};
  sample.q_wl_wxyz = {0.5, 0.5, 0.5, 0.5};
  sample.v_w_m_s = {4, 5, 6};
  sample.omega_l_rad_s = {7, 8, 9};
  sample.position_var_m2 = {0.1, 0.2, 0.3};
  sample.velocity_var_m2_s2 = {0.4, 0.5, 0.6};
  sample.gyro_saturated_axes = 0b100;
  sample.lidar_corrected = true;
  // The sample's bytes arrived 3 ms ago.
  sample.imu_arrival_steady_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count() -
      3'000'000;
  odometry_.push(sample);
  sample.t_s += 0.01;
  sample.gyro_saturated_axes = 0;
  sample.imu_arrival_steady_ns = 0;  // unknown
  odometry_.push(sample);
  EXPECT_EQ(publisher.publish_pending(), 2u);
  deliver();
  ASSERT_EQ(odometry_inbox_.messages.size(), 2u);
  const tumble::odometry_t& m = odometry_inbox_.messages[0];
  EXPECT_EQ(odometry_inbox_.channels[0], "TEST_ODOM");
  EXPECT_EQ(m.utime, 1700000000250000);
  EXPECT_EQ(m.seq, 0);
  EXPECT_EQ(odometry_inbox_.messages[1].seq, 1);
  EXPECT_EQ(m.position_m[2], 3.0);
  EXPECT_EQ(m.orientation[0], 0.5);
  EXPECT_EQ(m.velocity_m_s[1], 5.0);
  EXPECT_EQ(m.angular_velocity_rad_s[2], 9.0);
  EXPECT_EQ(m.position_var_m2[0], 0.1);
  EXPECT_EQ(m.velocity_var_m2_s2[2], 0.6);
  const int expected_flags = static_cast<int>(tumble::odometry_t::FLAG_INITIALISED) |
                             static_cast<int>(tumble::odometry_t::FLAG_LIDAR_CORRECTED) |
                             static_cast<int>(tumble::odometry_t::FLAG_GYRO_SATURATED);
  EXPECT_EQ(m.flags, expected_flags);
  EXPECT_EQ(odometry_inbox_.messages[1].flags & tumble::odometry_t::FLAG_GYRO_SATURATED, 0);
  EXPECT_GE(m.latency_ms, 3.0f);
  EXPECT_LT(m.latency_ms, 60'000.0f);
  EXPECT_EQ(odometry_inbox_.messages[1].latency_ms, 0.0f);
  EXPECT_EQ(publisher.published(LcmPublisher::kOdometry), 2u);
  EXPECT_EQ(publisher.failed(LcmPublisher::kOdometry), 0u);
}

TEST_F(LcmPublisherTest, RegistrationDecodesWithItsContentAndReachesObservers) {
  struct Recorder : RegistrationObserver {
    std::vector<std::int64_t> indices;
    void on_registration(const RegistrationRecord& r) override { indices.push_back(r.scan_index); }
  } observer;
  LcmPublisher publisher(lcm_, LcmChannels::with_prefix("TEST_"), inputs(), {"deskew", "weights", "icp"}, wakeup_);
  publisher.add_observer(observer);
  RegistrationRecord r;
  r.t_s = 12.5;
  r.scan_index = 42;
  r.position_m = {1, 2, 3};
  r.covariance[35] = 0.01;
  r.iterations = 7;
  r.converged = true;
  r.inlier_ratio = 0.6f;
  r.degeneracy = 0.2f;
  r.model = WeightModel::VTW;
  r.deskew = false;
  r.points_in = 28800;
  r.points_used = 9000;
  r.num_stages = 3;
  r.stage_ms = {1.5f, 2.5f, 30.0f};
  r.map_deferred = true;
  registrations_.push(r);
  EXPECT_EQ(publisher.publish_pending(), 1u);
  deliver();
  ASSERT_EQ(pose_inbox_.messages.size(), 1u);
  const tumble::registration_t& m = pose_inbox_.messages[0];
  EXPECT_EQ(m.utime, 12500000);
  EXPECT_EQ(m.scan_index, 42);
  EXPECT_EQ(m.position_m[1], 2.0);
  EXPECT_EQ(m.covariance[35], 0.01);
  EXPECT_EQ(m.iterations, 7);
  EXPECT_TRUE(m.converged);
  EXPECT_FLOAT_EQ(m.inlier_ratio, 0.6f);
  EXPECT_EQ(m.model, "VTW");
  EXPECT_FALSE(m.deskew);
  EXPECT_EQ(m.points_used, 9000);
  ASSERT_EQ(m.num_stages, 3);
  EXPECT_EQ(m.stage_name, (std::vector<std::string>{"deskew", "weights", "icp"}));
  EXPECT_EQ(m.stage_ms, (std::vector<float>{1.5f, 2.5f, 30.0f}));
  EXPECT_TRUE(m.map_deferred);
  EXPECT_EQ(observer.indices, (std::vector<std::int64_t>{42}));
}

std::int64_t steady_ns_ago(double ms) {
  const auto now =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
  return now - static_cast<std::int64_t>(ms * 1e6);
}

TEST_F(LcmPublisherTest, StatusCarriesThePeriodsLatenciesAndTheRunKeepsThemAll) {
  LcmPublisher publisher(lcm_, LcmChannels::with_prefix("TEST_"), inputs(), {}, wakeup_);
  TrajectoryRecord sample;
  for (int i = 0; i < 4; ++i) {
    sample.t_s = i;
    sample.imu_arrival_steady_ns = steady_ns_ago(i == 3 ? 500.0 : 2.0);
    odometry_.push(sample);
  }
  RegistrationRecord scan;
  scan.scan_complete_steady_ns = steady_ns_ago(40.0);
  registrations_.push(scan);
  status_.draft().num_stages = 0;
  status_.publish();
  publisher.publish_pending();
  status_.publish();  // the next period: nothing published in it
  publisher.publish_pending();
  deliver();
  ASSERT_EQ(status_inbox_.messages.size(), 2u);
  const tumble::status_t& first = status_inbox_.messages[0];
  EXPECT_GE(first.odometry_latency_p50_ms, 2.0f);
  EXPECT_LT(first.odometry_latency_p50_ms, 400.0f);
  EXPECT_GE(first.odometry_latency_max_ms, 500.0f);
  EXPECT_GE(first.odometry_latency_p99_ms, 500.0f);  // 1 of 4 is above the 99th percentile's rank
  EXPECT_GE(first.pose_latency_p50_ms, 40.0f);
  EXPECT_GE(first.pose_latency_max_ms, 40.0f);
  EXPECT_TRUE(std::isnan(status_inbox_.messages[1].odometry_latency_p50_ms));
  EXPECT_TRUE(std::isnan(status_inbox_.messages[1].pose_latency_max_ms));
  EXPECT_EQ(publisher.odometry_latency().count(), 4u);
  EXPECT_EQ(publisher.pose_latency().count(), 1u);
}

TEST_F(LcmPublisherTest, StatusScanAndMapDecodeWithTheirContent) {
  LcmPublisher publisher(lcm_, LcmChannels::with_prefix("TEST_"), inputs(), {}, wakeup_);
  tumble::status_t& status = status_.draft();
  status.utime = 99;
  status.state = tumble::status_t::STATE_TRACKING;
  status.state_name = "tracking";
  status.num_rings = 1;
  status.ring_name = {"imu"};
  status.ring_fill = {0.25f};
  status.ring_drops = {3};
  status.num_stages = 0;
  status_.publish();
  tumble::scan_t& scan = scans_.draft();
  scan.utime = 100;
  scan.scan_index = 5;
  scan.num_points = 2;
  scan.x_m = {1, 2};
  scan.y_m = {3, 4};
  scan.z_m = {5, 6};
  scan.sigma_s_m = {0.1f, 0.2f};
  scan.weight = {1.0f, 0.5f};
  scan.ring = {0, 15};
  scans_.publish();
  tumble::map_t& map = maps_.draft();
  map.scan_index = 5;
  map.map_points = 40;
  map.points_per_voxel = 4;
  map.num_points = 1;
  map.x_m = {7};
  map.y_m = {8};
  map.z_m = {9};
  maps_.publish();
  EXPECT_EQ(publisher.publish_pending(), 3u);
  EXPECT_EQ(publisher.publish_pending(), 0u);  // mailboxes are taken once
  deliver();
  ASSERT_EQ(status_inbox_.messages.size(), 1u);
  EXPECT_EQ(status_inbox_.messages[0].state_name, "tracking");
  EXPECT_EQ(status_inbox_.messages[0].ring_drops, (std::vector<std::int64_t>{3}));
  ASSERT_EQ(scan_inbox_.messages.size(), 1u);
  EXPECT_EQ(scan_inbox_.messages[0].num_points, 2);
  EXPECT_EQ(scan_inbox_.messages[0].weight, (std::vector<float>{1.0f, 0.5f}));
  EXPECT_EQ(scan_inbox_.messages[0].ring, (std::vector<std::int8_t>{0, 15}));
  EXPECT_EQ(scan_inbox_.channels[0], "TEST_SCAN");
  ASSERT_EQ(map_inbox_.messages.size(), 1u);
  EXPECT_EQ(map_inbox_.messages[0].map_points, 40);
  EXPECT_EQ(map_inbox_.messages[0].z_m, (std::vector<float>{9}));
  EXPECT_EQ(map_inbox_.channels[0], "TEST_MAP");
}

TEST_F(LcmPublisherTest, FailedPublishesAreCountedNotFatal) {
  // An LCM log opened for reading refuses to publish.
  const std::string log =
      (std::filesystem::temp_directory_path() / ("tumble_lcm_" + std::to_string(::getpid()) + ".lcmlog")).string();
  {
    lcm::LCM writer("file://" + log + "?mode=w");
    const std::uint8_t byte = 0;
    writer.publish("ANY", &byte, 1);  // a log needs one event to be readable
  }
  lcm::LCM reader("file://" + log + "?mode=r");
  ASSERT_TRUE(reader.good());
  LcmPublisher publisher(reader, LcmChannels::with_prefix("TEST_"), inputs(), {}, wakeup_);
  for (int i = 0; i < 5; ++i) odometry_.push(TrajectoryRecord{});
  publisher.publish_pending();
  std::filesystem::remove(log);
  EXPECT_EQ(publisher.failed(LcmPublisher::kOdometry), 5u);
  EXPECT_EQ(publisher.published(LcmPublisher::kOdometry), 0u);
  EXPECT_TRUE(odometry_.empty());
}

TEST_F(LcmPublisherTest, NullInputsAreNotPublished) {
  LcmPublisher publisher(lcm_, LcmChannels::with_prefix("TEST_"), {&odometry_, nullptr, nullptr, nullptr}, {}, wakeup_);
  registrations_.push(RegistrationRecord{});
  EXPECT_EQ(publisher.publish_pending(), 0u);
  EXPECT_EQ(registrations_.size(), 1u);
}

TEST_F(LcmPublisherTest, SteadyStateOdometryPublishingDoesNotAllocateInTheDaemon) {
  // Conversion and encoding reuse their buffers; what LCM's memq provider
  // allocates per message is outside the daemon, so encode-only is counted.
  tumble::odometry_t message{};
  std::vector<std::uint8_t> buffer(message.getEncodedSize());
  TrajectoryRecord sample;
  test::AllocationCounter allocations;
  for (int i = 0; i < 100; ++i) {
    sample.t_s = i;
    odometry_.push(sample);
    odometry_.pop_with([&](const TrajectoryRecord& s) {
      to_lcm(s, i, 0.5f, message);
      message.encode(buffer.data(), 0, static_cast<int>(buffer.size()));
    });
  }
  EXPECT_EQ(allocations.count(), 0u);
}

}  // namespace
}  // namespace tumble::daemon
