#include "daemon/lcm_publisher.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <string>
#include <utility>

#include "daemon/lcm_messages.hpp"
#include "daemon/steady_time.hpp"
#include "daemon/thread_setup.hpp"

namespace tumble::daemon {

LcmChannels LcmChannels::with_prefix(const std::string& prefix) {
  return {prefix + "ODOM", prefix + "POSE", prefix + "STATUS", prefix + "SCAN", prefix + "MAP"};
}

LcmPublisher::LcmPublisher(lcm::LCM& lcm, LcmChannels channels, PublisherInputs inputs,
                           std::vector<std::string> stage_names, Wakeup& wakeup)
    : lcm_(lcm),
      channel_names_{std::move(channels.odometry), std::move(channels.pose), std::move(channels.status),
                     std::move(channels.scan), std::move(channels.map)},
      inputs_(inputs),
      stage_names_(std::move(stage_names)),
      buffer_(64 * 1024),
      wakeup_(wakeup) {}

LcmPublisher::~LcmPublisher() { stop(); }

void LcmPublisher::add_observer(RegistrationObserver& observer) { observers_.push_back(&observer); }

template <class Message>
void LcmPublisher::publish(Channel channel, const Message& message) {
  const int size = message.getEncodedSize();
  if (buffer_.size() < static_cast<std::size_t>(size)) buffer_.resize(static_cast<std::size_t>(size));
  const bool ok = message.encode(buffer_.data(), 0, size) == size &&
                  lcm_.publish(channel_names_[channel], buffer_.data(), static_cast<unsigned>(size)) == 0;
  (ok ? published_ : failed_)[channel].fetch_add(1, std::memory_order_relaxed);
  if (!ok) {
    const double now_s = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    warnings_.warn(channel_names_[channel], now_s, "LCM: publishing on {} failed ({} so far)", channel_names_[channel],
                   failed_[channel].load(std::memory_order_relaxed));
  }
}

std::size_t LcmPublisher::publish_pending() {
  std::size_t count = 0;
  if (inputs_.odometry) {
    while (inputs_.odometry->pop_with([this](const TrajectoryRecord& sample) {
      const float latency_ms = latency_ms_since(sample.imu_arrival_steady_ns);
      to_lcm(sample, odometry_seq_++, latency_ms, odometry_message_);
      publish(kOdometry, odometry_message_);
      if (sample.imu_arrival_steady_ns != 0) odometry_latency_.add(latency_ms);
    }))
      ++count;
  }
  if (inputs_.registrations) {
    while (inputs_.registrations->pop_with([this](const RegistrationRecord& r) {
      const float latency_ms = latency_ms_since(r.scan_complete_steady_ns);
      to_lcm(r, stage_names_, latency_ms, registration_message_);
      publish(kPose, registration_message_);
      if (r.scan_complete_steady_ns != 0) pose_latency_.add(latency_ms);
      for (RegistrationObserver* observer : observers_) observer->on_registration(r);
    }))
      ++count;
  }
  if (inputs_.status) {
    if (tumble::status_t* status = inputs_.status->take()) {
      const LatencyHistogram& odometry = odometry_latency_.period;
      const LatencyHistogram& pose = pose_latency_.period;
      status->odometry_latency_p50_ms = static_cast<float>(odometry.percentile_ms(0.5));
      status->odometry_latency_p99_ms = static_cast<float>(odometry.percentile_ms(0.99));
      status->odometry_latency_max_ms = static_cast<float>(odometry.max_ms());
      status->pose_latency_p50_ms = static_cast<float>(pose.percentile_ms(0.5));
      status->pose_latency_max_ms = static_cast<float>(pose.max_ms());
      odometry_latency_.period.reset();
      pose_latency_.period.reset();
      publish(kStatus, *status);
      ++count;
    }
  }
  if (inputs_.scans) {
    if (const tumble::scan_t* scan = inputs_.scans->take()) {
      publish(kScan, *scan);
      ++count;
    }
  }
  if (inputs_.maps) {
    if (const tumble::map_t* map = inputs_.maps->take()) {
      publish(kMap, *map);
      ++count;
    }
  }
  return count;
}

bool LcmPublisher::has_pending() const {
  return (inputs_.odometry && !inputs_.odometry->empty()) ||
         (inputs_.registrations && !inputs_.registrations->empty()) || (inputs_.status && inputs_.status->has_new()) ||
         (inputs_.scans && inputs_.scans->has_new()) || (inputs_.maps && inputs_.maps->has_new());
}

void LcmPublisher::start(int realtime_priority) {
  stopping_.store(false, std::memory_order_relaxed);
  thread_ = std::thread([this, realtime_priority] {
    name_this_thread("tumble-publish");
    if (const std::string error = set_realtime_priority(realtime_priority); !error.empty())
      spdlog::warn("tumble-publish: {}", error);
    run();
  });
}

void LcmPublisher::run() {
  while (!stopping_.load(std::memory_order_acquire)) {
    if (publish_pending() == 0) {
      wakeup_.wait(std::chrono::milliseconds(50),
                   [this] { return has_pending() || stopping_.load(std::memory_order_acquire); });
    }
    heartbeat_.fetch_add(1, std::memory_order_relaxed);
  }
  publish_pending();
}

void LcmPublisher::stop() {
  if (!thread_.joinable()) return;
  stopping_.store(true, std::memory_order_release);
  wakeup_.notify();
  thread_.join();
}

}  // namespace tumble::daemon
