#include "tools/sim/live.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>

#include "tools/sim/live_mti.hpp"
#include "tools/sim/live_sinks.hpp"
#include "tools/sim/sim_run.hpp"

namespace tumble::sim {
namespace {

constexpr std::int64_t kLateNs = 1'000'000;
constexpr std::int64_t kStartLeadNs = 20'000'000;  // time to set up before the first event
constexpr std::int64_t kMeasuringCheckNs = 10'000'000;  // waiting for the device to measure

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
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

  MtiDeviceOptions device = options.mti;
  device.baud = static_cast<std::uint32_t>(run.scenario().imu_link.baud);
  LiveMti mti(pty, device, clock_ns(CLOCK_MONOTONIC));
  LiveSummary summary;
  while (options.start_when_measuring && !mti.device().measuring()) {
    if (!mti.wait_until(clock_ns(CLOCK_MONOTONIC) + kMeasuringCheckNs, stop)) {
      summary.stopped = true;
      return summary;
    }
  }
  // Run time 0 is a moment from now on both clocks; the lidar header clock is
  // the host's real-time clock, as with a synced unit.
  const std::int64_t start_mono_ns = clock_ns(CLOCK_MONOTONIC) + kStartLeadNs;
  run.set_epoch_ns((clock_ns(CLOCK_REALTIME) + kStartLeadNs) / 1000 * 1000);
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
    if (!mti.wait_until(due_ns, stop)) {
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
      mti.stream(read.bytes);
      ++summary.imu_reads;
      summary.imu_bytes += read.bytes.size();
      have_read = imu.next(read);
    }
  }
  summary.imu_bytes_dropped = pty.dropped_bytes();
  summary.imu_bytes_held = mti.counts().stream_bytes_held;
  summary.imu_baud_mismatch_bytes = mti.counts().baud_mismatch_bytes;
  summary.mti_requests = mti.device().counts().requests;
  summary.mti_errors_sent = mti.device().counts().errors_sent;
  return summary;
}

}  // namespace tumble::sim
