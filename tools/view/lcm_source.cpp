#include "tools/view/lcm_source.hpp"

#include <spdlog/spdlog.h>

#include <memory>
#include <stdexcept>

#include "tools/view/frames.hpp"

namespace tumble::view {
namespace {

constexpr int kQueueCapacity = 4;  // messages LCM holds per channel for this thread

template <class Message>
bool decode(const lcm::ReceiveBuffer* buffer, Message& message) {
  return message.decode(buffer->data, 0, static_cast<int>(buffer->data_size)) >= 0;
}

}  // namespace

LcmSource::LcmSource(const std::string& url, const std::string& channel_prefix, LiveState& state)
    : lcm_(url), prefix_(channel_prefix), state_(state) {
  if (!lcm_.good()) throw std::runtime_error("cannot open LCM at " + url);
  for (const char* name : {"STATUS", "POSE", "ODOM", "SCAN", "MAP"}) {
    lcm::Subscription* s = lcm_.subscribe(prefix_ + name, &LcmSource::on_message, this);
    s->setQueueCapacity(kQueueCapacity);
  }
}

LcmSource::~LcmSource() { stop(); }

void LcmSource::start() {
  thread_ = std::thread([this] {
    while (!stopping_.load(std::memory_order_relaxed)) lcm_.handleTimeout(100);
  });
}

void LcmSource::stop() {
  stopping_.store(true, std::memory_order_relaxed);
  if (thread_.joinable()) thread_.join();
}

void LcmSource::on_message(const lcm::ReceiveBuffer* buffer, const std::string& channel) {
  const std::string name = channel.substr(prefix_.size());
  if (name == "STATUS") {
    tumble::status_t m;
    if (decode(buffer, m)) state_.add(std::make_shared<const Frame>(status_frame(m)));
  } else if (name == "POSE") {
    tumble::registration_t m;
    if (decode(buffer, m)) state_.add_pose(std::make_shared<const Frame>(pose_frame(m)), m.scan_index, m.position_m);
  } else if (name == "ODOM") {
    const auto now = std::chrono::steady_clock::now();
    if (now < next_odometry_) return;
    next_odometry_ = now + kOdometryPeriod;
    tumble::odometry_t m;
    if (decode(buffer, m)) state_.add(std::make_shared<const Frame>(odometry_frame(m)));
  } else if (name == "SCAN") {
    tumble::scan_t m;
    if (decode(buffer, m)) state_.add(std::make_shared<const Frame>(scan_frame(m)));
  } else if (name == "MAP") {
    tumble::map_t m;
    if (decode(buffer, m)) state_.add(std::make_shared<const Frame>(map_frame(m)));
  }
}

}  // namespace tumble::view
