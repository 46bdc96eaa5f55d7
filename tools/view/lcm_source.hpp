// Subscribes to tumbled's channels (it publishes nothing: the view is
// read-only on LCM) and turns each message into a frame for LiveState, on a
// thread of its own. LCM's own queue per channel is kept short, so a burst
// drops old messages there rather than growing.
#pragma once

#include <atomic>
#include <chrono>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>

#include "tools/view/live_state.hpp"

namespace tumble::view {

class LcmSource {
 public:
  // Throws std::runtime_error when the URL cannot be opened.
  LcmSource(const std::string& url, const std::string& channel_prefix, LiveState& state);
  ~LcmSource();
  LcmSource(const LcmSource&) = delete;
  LcmSource& operator=(const LcmSource&) = delete;

  void start();
  void stop();

 private:
  void on_message(const lcm::ReceiveBuffer* buffer, const std::string& channel);

  lcm::LCM lcm_;
  std::string prefix_;
  LiveState& state_;
  // The fused pose comes at the IMU's rate; browsers get it at most this often.
  std::chrono::steady_clock::time_point next_odometry_{};
  static constexpr std::chrono::milliseconds kOdometryPeriod{40};
  std::atomic<bool> stopping_{false};
  std::thread thread_;
};

}  // namespace tumble::view
