#include "daemon/run.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "daemon/lcm_messages.hpp"
#include "daemon/lcm_publisher.hpp"
#include "daemon/status_aggregator.hpp"
#include "daemon/systemd_notify.hpp"
#include "daemon/scan_log.hpp"
#include "daemon/steady_time.hpp"
#include "daemon/trajectory_file.hpp"

namespace tumble::daemon {

namespace {

// The run's latencies, for the operator and for measuring (docs/results.md, Speed).
// Replaying at --rate max, the input waits in full rings by design: the
// figures then measure the queues, and the line says so.
void log_latency_summary(const LcmPublisher& publisher, bool lossless_replay) {
  const LatencyHistogram& odometry = publisher.odometry_latency();
  const LatencyHistogram& pose = publisher.pose_latency();
  if (odometry.count() == 0 && pose.count() == 0) return;
  spdlog::info(
      "latency over the run: IMU bytes read -> TUMBLE_ODOM p50 {:.3f} ms, p99 {:.3f} ms, max {:.3f} ms ({} samples); "
      "scan complete -> TUMBLE_POSE p50 {:.1f} ms, p99 {:.1f} ms, max {:.1f} ms ({} scans){}",
      odometry.percentile_ms(0.5), odometry.percentile_ms(0.99), odometry.max_ms(), odometry.count(),
      pose.percentile_ms(0.5), pose.percentile_ms(0.99), pose.max_ms(), pose.count(),
      lossless_replay ? " (replay at --rate max: input queued by design, not a latency)" : "");
}

std::int64_t host_utime_now() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

const char* present(bool yes) { return yes ? "yes" : "none"; }

}  // namespace

RunOptions run_options(const CommandLine& command_line) {
  return {command_line.replay, command_line.rate, command_line.trajectory_out, command_line.scan_log};
}

int run_daemon(const DaemonConfig& config, const RunOptions& options, lcm::LCM& lcm, ShutdownSignals& signals,
               const PartsFactory& make_parts) {
  const SystemdNotifier systemd;
  const std::chrono::nanoseconds status_period(std::llround(config.daemon.status_period_s * 1e9));
  std::chrono::nanoseconds tick = status_period;
  if (const auto watchdog = systemd.watchdog_timeout()) tick = std::min<std::chrono::nanoseconds>(tick, *watchdog / 2);
  MainLoop loop(signals, tick);  // before the pipeline: its threads wake the loop until they are joined

  const bool lossless = options.replay && options.rate.max;
  // A replay's health follows the data's own time (status_aggregator.hpp).
  const bool sensor_time = options.replay.has_value();
  Pipeline pipeline(config, lossless ? OverflowPolicy::Wait : OverflowPolicy::DropOldest,
                    sensor_time ? HealthClock::Sensor : HealthClock::Steady);
  PipelineParts parts = make_parts(pipeline.io_context(), config, options);
  if (options.replay && (!parts.lidar_source || !parts.imu_source)) {
    spdlog::error("--replay: this build has no lidar and IMU replay sources");
    return 1;
  }
  if (!config.record.dir.empty() && !parts.recorder) {
    spdlog::error("record.dir: this build has no recorder");
    return 1;
  }
  std::optional<TrajectoryFile> trajectory;
  if (options.trajectory_out)
    trajectory.emplace(*options.trajectory_out, config.daemon.checkpoint_period_s,
                       pipeline.counters().trajectory_lines_lost);
  spdlog::info("parts: lidar source {}, IMU source {}, fuser {}, registration {}, recorder {}",
               present(parts.lidar_source != nullptr), present(parts.imu_source != nullptr),
               present(parts.fuser != nullptr), present(parts.registration != nullptr),
               present(parts.recorder != nullptr));

  const std::vector<std::string> stage_names =
      parts.registration ? parts.registration->stage_names() : std::vector<std::string>{};
  LcmPublisher publisher(lcm, LcmChannels::with_prefix(config.lcm.channel_prefix), pipeline.publisher_inputs(),
                         stage_names, pipeline.output_wakeup());
  if (trajectory) publisher.add_observer(*trajectory);
  std::optional<ScanLog> scan_log;
  if (options.scan_log) {
    scan_log.emplace(*options.scan_log, stage_names, config.daemon.health);
    publisher.add_observer(*scan_log);
  }
  StatusAggregator status(config.daemon.health, stage_names, pipeline.rings(), pipeline.counters(),
                          pipeline.scan_reports(), steady_now_ns());
  const auto publish_status = [&] {
    status.tick(steady_now_ns(), host_utime_now(), pipeline.status_mailbox().draft());
    pipeline.status_mailbox().publish();
    pipeline.output_wakeup().notify();
  };
  // Sensor time: each tick evaluates the health machine; the status goes out
  // at each status period of data time, stamped with it.
  double next_sensor_status_s = -1.0;
  SensorTimeTick newest_tick;
  const auto follow_sensor_time = [&] {
    SensorTimeTick tick;
    while (pipeline.health_ticks().pop(tick)) {
      status.evaluate(tick);
      newest_tick = tick;
      if (next_sensor_status_s < 0.0) next_sensor_status_s = tick.t_s + config.daemon.status_period_s;
      if (tick.t_s + 1e-9 < next_sensor_status_s) continue;
      status.publish(std::llround(tick.t_s * 1e9), std::llround(tick.t_s * 1e6), pipeline.status_mailbox().draft());
      pipeline.status_mailbox().publish();
      pipeline.output_wakeup().notify();
      systemd.status(status.summary());
      next_sensor_status_s += config.daemon.status_period_s;
    }
  };

  publisher.start(config.daemon.realtime_priority);
  pipeline.start(std::move(parts), [&loop] { loop.wake(); });
  // systemd's READY=1 means "localising can start": both sensors deliver.
  const PipelineCounters& counters = pipeline.counters();
  const auto sensors_deliver = [&counters] {
    return counters.lidar_packets.load(std::memory_order_relaxed) > 0 &&
           counters.imu_samples.load(std::memory_order_relaxed) > 0;
  };
  bool ready = false;
  systemd.status("waiting for sensors");
  spdlog::info("running: LCM {} channels {}*, model {}, de-skew {}", config.lcm.url, config.lcm.channel_prefix,
               to_string(config.registration.model), config.registration.deskew ? "on" : "off");

  std::int64_t next_status_ns = steady_now_ns() + status_period.count();
  std::uint64_t publisher_heartbeat = publisher.heartbeat();
  bool stalled = false;
  bool drain = false;
  int exit_code = 0;
  for (;;) {
    const MainLoop::Event event = loop.wait();
    if (event == MainLoop::Event::Signal) {
      spdlog::info("{}: stopping", strsignal(loop.last_signal()));
      break;
    }
    if (const auto failure = pipeline.failure()) {
      spdlog::critical("{}", *failure);
      exit_code = 1;
      break;
    }
    if (sensor_time) follow_sensor_time();
    if (pipeline.input_ended() && (!sensor_time || pipeline.health_ticks_complete())) {
      if (sensor_time) follow_sensor_time();  // the ticks pushed before it said complete
      if (!options.replay) {  // live sensors do not end: let systemd restart us
        spdlog::critical("live sensor input ended");
        exit_code = 1;
        break;
      }
      spdlog::info("replay input finished: processing what is queued");
      drain = true;
      break;
    }
    if (!ready && sensors_deliver()) {
      ready = true;
      systemd.ready();
      spdlog::info("both sensors deliver: ready");
    }
    if (event != MainLoop::Event::Tick) continue;
    const std::int64_t now = steady_now_ns();
    if (!sensor_time && now >= next_status_ns) {
      publish_status();
      systemd.status(status.summary());
      while (next_status_ns <= now) next_status_ns += status_period.count();
    }
    if (systemd.watchdog_timeout()) {
      const bool publisher_alive = publisher.heartbeat() != publisher_heartbeat;
      publisher_heartbeat = publisher.heartbeat();
      // Both checks run every time: threads_alive() also records the new heartbeats.
      const bool alive = pipeline.threads_alive() && publisher_alive;
      if (alive) {
        systemd.watchdog();
      } else if (!stalled) {
        spdlog::error("a pipeline thread made no progress: withholding the watchdog ping");
      }
      stalled = !alive;
    }
  }

  systemd.stopping();
  if (drain) status.input_ended();
  pipeline.stop_reporting_health();
  pipeline.stop(drain ? Pipeline::Drain::Yes : Pipeline::Drain::No);
  const bool on_data_time = sensor_time && newest_tick.t_s > 0.0;
  const std::int64_t data_time_ns = std::llround(newest_tick.t_s * 1e9);
  if (drain) status.judge_final_scans(on_data_time ? data_time_ns : steady_now_ns());
  if (on_data_time) {  // the final counts, at the newest data time
    status.publish(data_time_ns, std::llround(newest_tick.t_s * 1e6), pipeline.status_mailbox().draft());
    pipeline.status_mailbox().publish();
    pipeline.output_wakeup().notify();
  } else {
    publish_status();  // the final counts
  }
  spdlog::info("final status: {}", status.summary());
  publisher.stop();
  log_latency_summary(publisher, lossless);
  if (trajectory) {
    if (trajectory->commit()) {
      spdlog::info("trajectory written to {}", trajectory->path());
    } else {
      exit_code = 1;  // the error lines say what is missing
    }
  }
  if (scan_log) {
    scan_log->commit();
    spdlog::info("scan log written to {}", scan_log->path());
  }
  spdlog::info("stopped");
  return exit_code;
}

}  // namespace tumble::daemon
