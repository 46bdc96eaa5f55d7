#include "tools/sim/live.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>

#include "tools/sim/live_sinks.hpp"
#include "tools/sim/sim_run.hpp"

namespace tumble::sim {
namespace {

constexpr std::int64_t kLateNs = 1'000'000;
constexpr std::int64_t kStartLeadNs = 20'000'000;  // time to set up before the first event
constexpr std::int64_t kStopCheckNs = 100'000'000;  // longest sleep without looking at `stop`

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

// False when `stop` was raised first.
bool sleep_until(std::int64_t due_ns, const std::atomic<bool>& stop) {
  while (!stop.load(std::memory_order_relaxed)) {
    const std::int64_t now = clock_ns(CLOCK_MONOTONIC);
    if (now >= due_ns) return true;
    const std::int64_t wake = std::min(due_ns, now + kStopCheckNs);
    const timespec ts{static_cast<time_t>(wake / 1'000'000'000), static_cast<long>(wake % 1'000'000'000)};
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);  // EINTR: loop and look at stop
  }
  return false;
}

}  // namespace

LiveSummary run_live(Scenario scenario, const LiveOptions& options, std::ostream& announce,
                     const std::atomic<bool>& stop) {
  if (!(options.rate > 0.0) || !std::isfinite(options.rate)) throw LiveError("--rate must be a positive number");
  const std::uint32_t destination = parse_ipv4(options.host);
  if (!is_loopback(destination) && !options.allow_remote)
    throw LiveError("refusing to send to " + options.host + ": not a loopback address (pass --allow-remote to insist)");
  if (options.duration_s) {
    if (!(*options.duration_s > 0.0)) throw LiveError("--duration must be a positive number of seconds");
    scenario.duration_s = std::min(scenario_duration_s(scenario), *options.duration_s);
  }

  SimRun run(std::move(scenario));
  ImuPty pty;
  UdpSender udp(destination);
  announce << "imu-pty " << pty.slave_path() << "\n"
           << "lidar-udp " << options.host << " " << options.msop_port << " " << options.difop_port << std::endl;

  // Run time 0 is a moment from now on both clocks; the lidar header clock is
  // the host's real-time clock, as with a synced unit.
  const std::int64_t start_mono_ns = clock_ns(CLOCK_MONOTONIC) + kStartLeadNs;
  run.set_epoch_ns((clock_ns(CLOCK_REALTIME) + kStartLeadNs) / 1000 * 1000);
  LiveSummary summary;
  LidarStream lidar = run.lidar_stream();
  ImuStream imu = run.imu_stream();
  LidarDatagram datagram;
  SerialRead read;
  bool have_datagram = lidar.next(datagram);
  bool have_read = imu.next(read);
  while (have_datagram || have_read) {
    const bool take_lidar = have_datagram && (!have_read || datagram.arrival_ns <= read.arrival_ns);
    const std::int64_t arrival_ns = take_lidar ? datagram.arrival_ns : read.arrival_ns;
    const std::int64_t due_ns = start_mono_ns + std::llround(static_cast<double>(arrival_ns) / options.rate);
    if (!sleep_until(due_ns, stop)) {
      summary.stopped = true;
      break;
    }
    const std::int64_t late_ns = clock_ns(CLOCK_MONOTONIC) - due_ns;
    if (late_ns > kLateNs) ++summary.late_events;
    summary.max_late_s = std::max(summary.max_late_s, static_cast<double>(late_ns) * 1e-9);
    if (take_lidar) {
      const std::uint16_t port = datagram.is_difop ? options.difop_port : options.msop_port;
      if (!udp.send(port, datagram.payload)) ++summary.udp_send_failures;
      ++(datagram.is_difop ? summary.difop_packets : summary.msop_packets);
      have_datagram = lidar.next(datagram);
    } else {
      pty.write(read.bytes);
      ++summary.imu_reads;
      summary.imu_bytes += read.bytes.size();
      have_read = imu.next(read);
    }
  }
  summary.imu_bytes_dropped = pty.dropped_bytes();
  return summary;
}

}  // namespace tumble::sim
