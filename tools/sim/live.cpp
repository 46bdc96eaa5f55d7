#include "tools/sim/live.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <thread>

#include "tools/sim/header_time.hpp"
#include "tools/sim/live_mti.hpp"
#include "tools/sim/live_sinks.hpp"
#include "tools/sim/sim_run.hpp"

namespace tumble::sim {
namespace {

constexpr std::int64_t kLateNs = 1'000'000;
constexpr std::int64_t kStartLeadNs = 20'000'000;  // time to set up before the first event
constexpr std::int64_t kMeasuringCheckNs = 10'000'000;  // waiting for the device to measure
constexpr std::int64_t kUnpluggedPollNs = 10'000'000;  // how often an unplugged wait looks at `stop`
constexpr std::int64_t kRestartedClockShiftNs = -86'400'000'000'000;  // a day behind

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

std::int64_t seconds_to_ns(double s) { return std::llround(s * 1e9); }

void check_outage(const char* option, const std::optional<LiveOutage>& outage) {
  if (outage && !(outage->at_s >= 0.0 && outage->duration_s > 0.0 && std::isfinite(outage->at_s + outage->duration_s)))
    throw LiveError(std::string(option) + ": needs T >= 0 and D > 0 (seconds)");
}

bool in_outage(const std::optional<LiveOutage>& outage, std::int64_t run_ns) {
  return outage && run_ns >= seconds_to_ns(outage->at_s) && run_ns < seconds_to_ns(outage->at_s + outage->duration_s);
}

// Points `link` at `target`, replacing what was there in one rename.
void point_link(const std::string& link, const std::string& target) {
  const std::filesystem::path temp = link + ".new";
  std::error_code ignored;
  std::filesystem::remove(temp, ignored);
  std::filesystem::create_symlink(target, temp);
  std::filesystem::rename(temp, link);
}

// The MTi on its pty, or nothing while it is unplugged.
class PluggedMti {
 public:
  PluggedMti(const MtiDeviceOptions& device, std::string link) : device_(device), link_(std::move(link)) { plug(); }
  ~PluggedMti() {
    std::error_code ignored;
    if (!link_.empty()) std::filesystem::remove(link_, ignored);
  }
  PluggedMti(const PluggedMti&) = delete;
  PluggedMti& operator=(const PluggedMti&) = delete;

  void plug() {
    pty_ = std::make_unique<ImuPty>();
    mti_ = std::make_unique<LiveMti>(*pty_, device_, clock_ns(CLOCK_MONOTONIC));
    if (!link_.empty()) point_link(link_, pty_->slave_path());
  }
  // The host reads EIO, and the device path is gone, as when a USB adapter is pulled.
  void unplug() {
    collect();
    std::error_code ignored;
    if (!link_.empty()) std::filesystem::remove(link_, ignored);
    mti_.reset();
    pty_.reset();
  }
  bool plugged() const { return mti_ != nullptr; }
  const std::string& announced_path() const { return link_.empty() ? pty_->slave_path() : link_; }
  LiveMti& mti() { return *mti_; }

  bool wait_until(std::int64_t due_ns, const std::atomic<bool>& stop) {
    if (mti_) return mti_->wait_until(due_ns, stop);
    while (!stop.load(std::memory_order_relaxed)) {
      const std::int64_t now = clock_ns(CLOCK_MONOTONIC);
      if (now >= due_ns) return true;
      std::this_thread::sleep_for(std::chrono::nanoseconds(std::min(due_ns - now, kUnpluggedPollNs)));
    }
    return false;
  }

  // Counts over every device plugged so far.
  void collect() {
    if (!mti_) return;
    totals_.bytes_dropped += pty_->dropped_bytes();
    totals_.bytes_held += mti_->counts().stream_bytes_held;
    totals_.baud_mismatch_bytes += mti_->counts().baud_mismatch_bytes;
    totals_.requests += mti_->device().counts().requests;
    totals_.errors_sent += mti_->device().counts().errors_sent;
  }
  struct Totals {
    std::uint64_t bytes_dropped = 0, bytes_held = 0, baud_mismatch_bytes = 0, requests = 0, errors_sent = 0;
  };
  const Totals& totals() const { return totals_; }

 private:
  MtiDeviceOptions device_;
  std::string link_;
  std::unique_ptr<ImuPty> pty_;
  std::unique_ptr<LiveMti> mti_;
  Totals totals_;
};

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
  check_outage("--lidar-restart", options.lidar_restart);
  check_outage("--imu-unplug", options.imu_unplug);

  SimRun run(std::move(scenario));
  MtiDeviceOptions device = options.mti;
  device.baud = static_cast<std::uint32_t>(run.scenario().imu_link.baud);
  PluggedMti mti(device, options.imu_link);
  UdpSender udp(destination);
  announce << "imu-pty " << mti.announced_path() << "\n"
           << "lidar-udp " << options.host << " " << options.msop_port << " " << options.difop_port << std::endl;

  LiveSummary summary;
  while (options.start_when_measuring && !mti.mti().device().measuring()) {
    if (!mti.wait_until(clock_ns(CLOCK_MONOTONIC) + kMeasuringCheckNs, stop)) {
      summary.stopped = true;
      return summary;
    }
  }
  // Run time 0 is a moment from now on both clocks; the lidar header clock is
  // the host's real-time clock, as with a synced unit.
  const std::int64_t start_mono_ns = clock_ns(CLOCK_MONOTONIC) + kStartLeadNs;
  run.set_epoch_ns((clock_ns(CLOCK_REALTIME) + kStartLeadNs) / 1000 * 1000);
  const std::int64_t restarted_ns =
      options.lidar_restart ? seconds_to_ns(options.lidar_restart->at_s + options.lidar_restart->duration_s) : 0;
  LidarStream lidar = run.lidar_stream();
  ImuStream imu = run.imu_stream();
  LidarDatagram datagram;
  SerialRead read;
  bool have_datagram = lidar.next(datagram);
  bool have_read = imu.next(read);
  while (have_datagram || have_read) {
    const bool take_lidar = have_datagram && (!have_read || datagram.arrival_ns <= read.arrival_ns);
    const std::int64_t arrival_ns = take_lidar ? datagram.arrival_ns : read.arrival_ns;
    const bool unplugged = in_outage(options.imu_unplug, arrival_ns);
    if (unplugged && mti.plugged()) mti.unplug();
    if (!unplugged && !mti.plugged()) mti.plug();
    const std::int64_t due_ns = start_mono_ns + std::llround(static_cast<double>(arrival_ns) / options.rate);
    if (!mti.wait_until(due_ns, stop)) {
      summary.stopped = true;
      break;
    }
    const std::int64_t late_ns = clock_ns(CLOCK_MONOTONIC) - due_ns;
    if (late_ns > kLateNs) ++summary.late_events;
    summary.max_late_s = std::max(summary.max_late_s, static_cast<double>(late_ns) * 1e-9);
    if (take_lidar) {
      if (in_outage(options.lidar_restart, arrival_ns)) {
        ++summary.lidar_restart_packets;
      } else {
        if (options.lidar_restart && arrival_ns >= restarted_ns)
          shift_header_time(datagram.payload, !datagram.is_difop, kRestartedClockShiftNs);
        const std::uint16_t port = datagram.is_difop ? options.difop_port : options.msop_port;
        if (!udp.send(port, datagram.payload)) ++summary.udp_send_failures;
        ++(datagram.is_difop ? summary.difop_packets : summary.msop_packets);
      }
      have_datagram = lidar.next(datagram);
    } else {
      if (mti.plugged()) {
        mti.mti().stream(read.bytes);
        ++summary.imu_reads;
        summary.imu_bytes += read.bytes.size();
      } else {
        ++summary.imu_unplugged_reads;
      }
      have_read = imu.next(read);
    }
  }
  mti.collect();
  summary.imu_bytes_dropped = mti.totals().bytes_dropped;
  summary.imu_bytes_held = mti.totals().bytes_held;
  summary.imu_baud_mismatch_bytes = mti.totals().baud_mismatch_bytes;
  summary.mti_requests = mti.totals().requests;
  summary.mti_errors_sent = mti.totals().errors_sent;
  return summary;
}

}  // namespace tumble::sim
