#include "tools/sim/live_mti.hpp"

#include <poll.h>
#include <time.h>

#include <algorithm>
#include <cmath>

namespace tumble::sim {
namespace {

constexpr std::int64_t kStopCheckNs = 100'000'000;  // longest wait without looking at `stop`

std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace

LiveMti::LiveMti(ImuPty& pty, const MtiDeviceOptions& options, std::int64_t start_mono_ns)
    : pty_(pty), device_(options, 0.0), start_mono_ns_(start_mono_ns) {
  // A reader that sets no speed of its own (cat, a test) reads at the device's.
  pty_.set_line_baud(device_.baud());
}

double LiveMti::device_time_s(std::int64_t mono_ns) const {
  return static_cast<double>(mono_ns - start_mono_ns_) * 1e-9;
}

bool LiveMti::line_speeds_match() const {
  const auto host_baud = pty_.line_baud();
  return !host_baud || *host_baud == device_.baud();
}

void LiveMti::send(std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) return;
  if (!line_speeds_match()) {
    counts_.baud_mismatch_bytes += bytes.size();
    return;
  }
  pty_.write(bytes);
}

void LiveMti::serve(std::int64_t now_ns) {
  const double now_s = device_time_s(now_ns);
  host_bytes_.clear();
  pty_.read_host(host_bytes_);
  if (!host_bytes_.empty()) {
    if (line_speeds_match())
      device_.on_host_bytes(host_bytes_, now_s);
    else
      counts_.baud_mismatch_bytes += host_bytes_.size();
  }
  replies_.clear();
  device_.take_due(now_s, replies_);
  counts_.reply_bytes += replies_.size();
  send(replies_);
}

bool LiveMti::wait_until(std::int64_t due_ns, const std::atomic<bool>& stop) {
  while (!stop.load(std::memory_order_relaxed)) {
    const std::int64_t now = monotonic_ns();
    serve(now);
    if (now >= due_ns) return true;
    std::int64_t wake = std::min(due_ns, now + kStopCheckNs);
    if (const auto reply_s = device_.next_due_s())
      wake = std::min(wake, start_mono_ns_ + static_cast<std::int64_t>(std::ceil(*reply_s * 1e9)));
    const std::int64_t wait_ns = std::max<std::int64_t>(wake - now, 0);
    const timespec timeout{static_cast<time_t>(wait_ns / 1'000'000'000), static_cast<long>(wait_ns % 1'000'000'000)};
    pollfd host{pty_.master_fd(), POLLIN, 0};
    ::ppoll(&host, 1, &timeout, nullptr);  // EINTR or readable: loop, serve and look at stop
  }
  return false;
}

void LiveMti::stream(std::span<const std::uint8_t> bytes) {
  if (!device_.measuring()) {
    counts_.stream_bytes_held += bytes.size();
    return;
  }
  send(bytes);
}

}  // namespace tumble::sim
