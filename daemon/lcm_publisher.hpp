// The publish thread: takes records from the pipeline's rings and mailboxes,
// converts them to tumble LCM messages, encodes them into reused buffers and
// publishes them. LCM may block (a full socket buffer); it does so here, off
// the sensor path, and a full ring upstream then drops its oldest records.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>
#include <vector>

#include "daemon/latency_histogram.hpp"
#include "daemon/mailbox.hpp"
#include "daemon/rate_limited_log.hpp"
#include "daemon/records.hpp"
#include "daemon/spsc_ring.hpp"
#include "daemon/wakeup.hpp"
#include "tumble/map_t.hpp"
#include "tumble/odometry_t.hpp"
#include "tumble/registration_t.hpp"
#include "tumble/scan_t.hpp"
#include "tumble/status_t.hpp"

namespace tumble::daemon {

struct LcmChannels {
  std::string odometry;  // <prefix>ODOM, tumble.odometry_t
  std::string pose;      // <prefix>POSE, tumble.registration_t
  std::string status;    // <prefix>STATUS, tumble.status_t
  std::string scan;      // <prefix>SCAN, tumble.scan_t
  std::string map;       // <prefix>MAP, tumble.map_t
  static LcmChannels with_prefix(const std::string& prefix);
};

// Inputs the publisher drains; owned by the pipeline. A null input is not published.
struct PublisherInputs {
  SpscRing<TrajectoryRecord>* odometry = nullptr;
  SpscRing<RegistrationRecord>* registrations = nullptr;
  Mailbox<tumble::status_t>* status = nullptr;
  Mailbox<tumble::scan_t>* scans = nullptr;
  Mailbox<tumble::map_t>* maps = nullptr;
};

// Sees every registered scan on the publish thread (e.g. the trajectory file).
class RegistrationObserver {
 public:
  virtual ~RegistrationObserver() = default;
  virtual void on_registration(const RegistrationRecord& registration) = 0;
};

class LcmPublisher {
 public:
  enum Channel : std::size_t { kOdometry, kPose, kStatus, kScan, kMap, kChannelCount };

  // wakeup: what the producers of `inputs` notify after pushing.
  LcmPublisher(lcm::LCM& lcm, LcmChannels channels, PublisherInputs inputs, std::vector<std::string> stage_names,
               Wakeup& wakeup);
  ~LcmPublisher();
  LcmPublisher(const LcmPublisher&) = delete;
  LcmPublisher& operator=(const LcmPublisher&) = delete;

  void add_observer(RegistrationObserver& observer);  // before start()

  // Publishes everything waiting, on the calling thread (the publish thread,
  // or a test without one). Returns the number of messages published.
  std::size_t publish_pending();

  // realtime_priority: as daemon.realtime_priority (0: normal scheduling).
  void start(int realtime_priority = 0);
  // Publishes what is still waiting, then joins the thread.
  void stop();

  std::uint64_t published(Channel c) const { return published_[c].load(std::memory_order_relaxed); }
  std::uint64_t failed(Channel c) const { return failed_[c].load(std::memory_order_relaxed); }
  // Input arrived -> message handed to LCM, over the whole run: read them
  // once stop() returned (the publish thread writes them).
  const LatencyHistogram& odometry_latency() const { return odometry_latency_.run; }
  const LatencyHistogram& pose_latency() const { return pose_latency_.run; }
  // Advances at least every 100 ms while the publish thread is alive.
  std::uint64_t heartbeat() const { return heartbeat_.load(std::memory_order_relaxed); }

 private:
  template <class Message>
  void publish(Channel channel, const Message& message);
  bool has_pending() const;
  void run();

  lcm::LCM& lcm_;
  std::array<std::string, kChannelCount> channel_names_;
  PublisherInputs inputs_;
  std::vector<std::string> stage_names_;
  std::vector<RegistrationObserver*> observers_;

  tumble::odometry_t odometry_message_{};
  tumble::registration_t registration_message_{};
  std::vector<std::uint8_t> buffer_;
  std::int64_t odometry_seq_ = 0;
  // Per status period (reported in status_t, then reset) and per run.
  struct Latencies {
    LatencyHistogram period, run;
    void add(double ms) {
      period.add(ms);
      run.add(ms);
    }
  };
  Latencies odometry_latency_, pose_latency_;
  RateLimitedLog warnings_{3, 10.0};  // per channel: a dead network must not flood the log

  std::array<std::atomic<std::uint64_t>, kChannelCount> published_{};
  std::array<std::atomic<std::uint64_t>, kChannelCount> failed_{};
  std::atomic<std::uint64_t> heartbeat_{0};
  std::atomic<bool> stopping_{false};
  Wakeup& wakeup_;
  std::thread thread_;
};

}  // namespace tumble::daemon
