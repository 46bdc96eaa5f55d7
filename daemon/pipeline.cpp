#include "daemon/pipeline.hpp"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "daemon/steady_time.hpp"
#include "daemon/thread_setup.hpp"

namespace tumble::daemon {

namespace {

constexpr auto kIdleWait = std::chrono::milliseconds(50);  // bounds how stale a heartbeat can get
constexpr auto kRoomPoll = std::chrono::microseconds(100);

std::size_t capacity(int configured) { return static_cast<std::size_t>(configured); }

}  // namespace

Pipeline::Pipeline(const DaemonConfig& config, OverflowPolicy policy, HealthClock clock)
    : policy_(policy),
      publish_scan_(config.lcm.publish_scan),
      publish_map_period_s_(config.lcm.publish_map_period_s),
      realtime_priority_(config.daemon.realtime_priority),
      registration_nice_(config.daemon.registration_nice),
      trajectory_wait_ns_(std::llround(config.daemon.trajectory_wait_s * 1e9)),
      trajectory_wait_s_(config.daemon.trajectory_wait_s),
      max_expected_error_m_(config.daemon.health.max_expected_error_m),
      sensor_time_(clock == HealthClock::Sensor),
      imu_(capacity(config.daemon.imu_ring_capacity)),
      lidar_(capacity(config.daemon.lidar_ring_capacity)),
      corrections_(capacity(config.daemon.correction_ring_capacity)),
      odometry_(capacity(config.daemon.odometry_ring_capacity)),
      registrations_(capacity(config.daemon.registration_ring_capacity)),
      scan_reports_(capacity(config.daemon.scan_report_ring_capacity)),
      ticks_in_(capacity(config.daemon.lidar_ring_capacity)),
      health_ticks_(capacity(config.daemon.scan_report_ring_capacity)),
      trajectory_(capacity(config.daemon.trajectory_buffer_capacity)),
      window_(capacity(config.daemon.trajectory_buffer_capacity)) {}

Pipeline::~Pipeline() { stop(Drain::No); }

PublisherInputs Pipeline::publisher_inputs() {
  return {&odometry_, &registrations_, &status_, publish_scan_ ? &scans_ : nullptr,
          publish_map_period_s_ > 0 ? &maps_ : nullptr};
}

std::vector<NamedRing> Pipeline::rings() const {
  return {{"imu", &imu_, true},
          {"lidar", &lidar_, true},
          {"corrections", &corrections_, true},
          {"odometry_out", &odometry_, false},
          {"registration_out", &registrations_, false},
          {"scan_reports", &scan_reports_, false}};
}

std::optional<std::string> Pipeline::failure() const {
  if (!failed_.load(std::memory_order_acquire)) return std::nullopt;
  return failure_;
}

void Pipeline::start(PipelineParts parts, std::function<void()> wake_main) {
  if (parts.lidar_source && (!parts.lidar_decoder || !parts.registration))
    throw std::invalid_argument("a lidar source needs a lidar decoder and a registration stage");
  if (parts.imu_source && (!parts.imu_decoder || !parts.fuser))
    throw std::invalid_argument("an IMU source needs an IMU decoder and a fuser stage");
  parts_ = std::move(parts);
  wake_main_ = std::move(wake_main);
  imu_input_ended_.store(!parts_.imu_source, std::memory_order_release);

  if (parts_.fuser) start_thread(fuser_thread_, "tumble-fuser", &Pipeline::run_fuser, Priority::ImuPath);
  if (parts_.registration)
    start_thread(registration_thread_, "tumble-register", &Pipeline::run_registration, Priority::Background);
  if (!parts_.lidar_source && !parts_.imu_source) return;

  emit_imu_ = [this](const ImuSample& sample) {
    wait_for_room(imu_, &io_blocked_on_imu_);
    newest_imu_s_ = imu_bytes_arrival_s_;
    counters_.last_imu_steady_ns.store(imu_bytes_steady_ns_, std::memory_order_relaxed);
    imu_.push(ImuArrival{sample, imu_bytes_steady_ns_});
    fuser_wakeup_.notify();
  };
  republish_ = [this](const TrajectoryRecord& record) { trajectory_.publish(record); };
  lidar_input_ended_.store(!parts_.lidar_source, std::memory_order_release);
  io_work_.emplace(io_.get_executor());
  io_heartbeat_timer_.emplace(io_);
  boost::asio::post(io_, [this] {
    beat_io();
    if (parts_.lidar_source) {
      ++sources_running_;
      parts_.lidar_source->start([this](const LidarDatagram& d) { on_lidar_datagram(d); },
                                 [this] {
                                   lidar_input_ended_.store(true, std::memory_order_release);
                                   registration_wakeup_.notify();
                                   on_source_end();
                                 });
    }
    if (parts_.imu_source) {
      ++sources_running_;
      parts_.imu_source->start([this](const ImuBytes& b) { on_imu_bytes(b); },
                               [this] {
                                 imu_input_ended_.store(true, std::memory_order_release);
                                 registration_wakeup_.notify();
                                 on_source_end();
                               });
    }
  });
  start_thread(io_thread_, "tumble-io", &Pipeline::run_io, Priority::ImuPath);
}

void Pipeline::start_thread(std::thread& thread, const char* name, void (Pipeline::*body)(), Priority priority) {
  thread = std::thread([this, name, body, priority] {
    name_this_thread(name);
    const std::string error = priority == Priority::ImuPath ? set_realtime_priority(realtime_priority_)
                                                            : lower_this_thread_priority(registration_nice_);
    if (!error.empty()) spdlog::warn("{}: {}", name, error);
    try {
      (this->*body)();
    } catch (const std::exception& e) {
      fail(std::string(name) + ": " + e.what());
    }
  });
}

void Pipeline::fail(std::string message) {
  bool expected = false;
  if (!failing_.compare_exchange_strong(expected, true)) return;  // keep the first failure
  failure_ = std::move(message);
  failed_.store(true, std::memory_order_release);
  if (wake_main_) wake_main_();
}

// ---- io thread ----------------------------------------------------------------

void Pipeline::run_io() { io_.run(); }

void Pipeline::beat_io() {
  io_heartbeat_.fetch_add(1, std::memory_order_relaxed);
  io_heartbeat_timer_->expires_after(kIdleWait);
  io_heartbeat_timer_->async_wait([this](const boost::system::error_code& error) {
    if (!error) beat_io();
  });
}

template <class T>
void Pipeline::wait_for_room(SpscRing<T>& ring, std::atomic<bool>* blocked) {
  if (policy_ != OverflowPolicy::Wait || !ring.full()) return;
  if (blocked != nullptr) {
    blocked->store(true, std::memory_order_release);
    registration_wakeup_.notify();  // the compute threads may be waiting on exactly this
    fuser_wakeup_.notify();
  }
  while (ring.full() && !abandon_.load(std::memory_order_acquire)) std::this_thread::sleep_for(kRoomPoll);
  if (blocked != nullptr) blocked->store(false, std::memory_order_release);
}

template <class T>
void Pipeline::push(SpscRing<T>& ring, const T& item) {
  wait_for_room(ring, nullptr);
  ring.push(item);
}

void Pipeline::advance_sensor_time(double t_s) {
  if (!sensor_time_) return;
  if (next_tick_ < 0) next_tick_ = static_cast<std::int64_t>(std::floor(t_s / kHealthPeriod_s)) + 1;
  bool pushed = false;
  // Integer tick numbers: no drift from adding up the period.
  for (double tick_s = static_cast<double>(next_tick_) * kHealthPeriod_s; t_s >= tick_s;
       tick_s = static_cast<double>(++next_tick_) * kHealthPeriod_s) {
    ticks_in_.push(SensorTimeTick{tick_s, newest_imu_s_, newest_lidar_s_, lidar_.pushed(), 0,
                                  counters_.lidar_foreign_rate_hz.load(std::memory_order_relaxed)});
    pushed = true;
  }
  if (pushed) registration_wakeup_.notify();
}

void Pipeline::on_lidar_datagram(const LidarDatagram& datagram) {
  advance_sensor_time(datagram.arrival_s);
  wait_for_room(lidar_, &io_blocked_on_lidar_);
  const bool has_points =
      lidar_.push_if([&](PointBlock& block) { return parts_.lidar_decoder->decode(datagram, block); });
  parts_.lidar_decoder->report(counters_);
  if (parts_.recorder && parts_.lidar_decoder->last_from_the_lidar()) {
    parts_.recorder->record_lidar(datagram);
    parts_.recorder->report(counters_);
  }
  if (has_points) {
    newest_lidar_s_ = datagram.arrival_s;
    counters_.last_lidar_steady_ns.store(steady_now_ns(), std::memory_order_relaxed);
    registration_wakeup_.notify();
  }
}

void Pipeline::on_imu_bytes(const ImuBytes& bytes) {
  advance_sensor_time(bytes.arrival_s);
  imu_bytes_arrival_s_ = bytes.arrival_s;
  imu_bytes_steady_ns_ = steady_now_ns();
  if (parts_.recorder) {
    parts_.recorder->record_imu(bytes);
    parts_.recorder->report(counters_);
  }
  parts_.imu_decoder->decode(bytes, emit_imu_);
  parts_.imu_decoder->report(counters_);
}

void Pipeline::on_source_end() {
  if (--sources_running_ > 0) return;
  input_ended_.store(true, std::memory_order_release);
  if (wake_main_) wake_main_();
}

// ---- fuser thread ---------------------------------------------------------------

bool Pipeline::fuser_may_add(double t_s, double previous_t_s) const {
  if (policy_ != OverflowPolicy::Wait || !parts_.registration) return true;
  // Read the newest point first: a scan completed by that point has its end
  // stored before it (release/acquire), or has been registered since.
  const double newest_point = newest_point_s_.load(std::memory_order_acquire);
  const double held_end = held_scan_end_s_.load(std::memory_order_acquire);
  // Past the held scan's end by more than trajectory_wait_s (an IMU gap): a
  // live run registers the scan before this sample arrives; so does a replay.
  if (held_end != std::numeric_limits<double>::infinity())
    return previous_t_s < held_end && t_s <= held_end + trajectory_wait_s_;
  if (t_s < newest_point) return true;
  if (lidar_input_ended_.load(std::memory_order_acquire) && lidar_.empty()) return true;
  // The io thread waits for room in the IMU ring, so no lidar data can come
  // before this sample goes, and the registration thread has taken all that
  // came: a lidar gap, in which no scan ends.
  return io_blocked_on_imu_.load(std::memory_order_acquire) && imu_.full() &&
         lidar_popped_.load(std::memory_order_acquire) == lidar_.pushed();
}

void Pipeline::run_fuser() {
  FuserStage& fuser = *parts_.fuser;
  ImuArrival arrival;
  const ImuSample& sample = arrival.sample;
  bool have_sample = false;
  double previous_t_s = -std::numeric_limits<double>::infinity();
  RegistrationRecord correction;
  TrajectoryRecord fused;
  const auto apply_corrections = [&] {
    bool applied = false;
    while (corrections_.pop(correction)) {
      fuser.add_correction(correction, republish_);
      corrections_applied_.fetch_add(1, std::memory_order_acq_rel);
      registration_wakeup_.notify();
      applied = true;
    }
    return applied;
  };
  for (;;) {
    fuser_heartbeat_.fetch_add(1, std::memory_order_relaxed);
    const int stop = fuser_stop_.load(std::memory_order_acquire);
    if (stop == 2) break;
    bool worked = apply_corrections();
    if (!have_sample) have_sample = imu_.pop(arrival);
    const bool may_add = have_sample && fuser_may_add(sample.t_s, previous_t_s);
    // The registration pushes a scan's correction before it opens the gate
    // (held_scan_end_s_ back to infinity): a gate seen open may have a
    // correction behind it, which must come before the sample. Applied after
    // it instead, the correction re-propagated a sample that depended on
    // timing, and replays differed in the last bits (then in metres).
    if (may_add) worked = apply_corrections() || worked;
    if (have_sample && !may_add && policy_ == OverflowPolicy::Wait) {
      const double held_end = held_scan_end_s_.load(std::memory_order_acquire);
      if (previous_t_s < held_end && sample.t_s > held_end + trajectory_wait_s_ &&
          fuser_past_scan_end_s_.load(std::memory_order_acquire) != held_end) {
        fuser_past_scan_end_s_.store(held_end, std::memory_order_release);
        registration_wakeup_.notify();
      }
    }
    if (may_add) {
      have_sample = false;
      worked = true;
      previous_t_s = sample.t_s;
      for (std::size_t k = 0; k < 3; ++k) {
        if (sample.accel_saturated[k]) counters_.accel_saturated_samples[k].fetch_add(1, std::memory_order_relaxed);
        if (sample.gyro_saturated[k]) counters_.gyro_saturated_samples[k].fetch_add(1, std::memory_order_relaxed);
      }
      const bool extended = fuser.add_imu(sample, fused);
      fuser_time_s_.store(sample.t_s, std::memory_order_release);
      counters_.fuser_initialised.store(extended, std::memory_order_relaxed);
      if (extended) {
        fused.imu_arrival_steady_ns = arrival.arrival_steady_ns;
        trajectory_.publish(fused);
        push(odometry_, fused);
        output_wakeup_.notify();
      }
      // After publishing: the registration thread compares this with the IMU
      // ring's push count to know whether more trajectory can come.
      counters_.imu_samples.fetch_add(1, std::memory_order_acq_rel);
      registration_wakeup_.notify();
    }
    if (worked) continue;
    if (stop == 1 && !have_sample) break;  // drained
    // Until something that decides the gate changes.
    const double held_end = held_scan_end_s_.load(std::memory_order_acquire);
    const double newest_point = newest_point_s_.load(std::memory_order_acquire);
    const bool lidar_ended = lidar_input_ended_.load(std::memory_order_acquire);
    const bool lidar_empty = lidar_.empty();
    const bool io_blocked = io_blocked_on_imu_.load(std::memory_order_acquire);
    const std::uint64_t lidar_popped = lidar_popped_.load(std::memory_order_acquire);
    fuser_wakeup_.wait(kIdleWait, [&] {
      return (!have_sample && !imu_.empty()) || !corrections_.empty() ||
             fuser_stop_.load(std::memory_order_acquire) != stop ||
             held_scan_end_s_.load(std::memory_order_acquire) != held_end ||
             newest_point_s_.load(std::memory_order_acquire) != newest_point ||
             lidar_input_ended_.load(std::memory_order_acquire) != lidar_ended || lidar_.empty() != lidar_empty ||
             io_blocked_on_imu_.load(std::memory_order_acquire) != io_blocked ||
             lidar_popped_.load(std::memory_order_acquire) != lidar_popped;
    });
  }
  fuser_finished_.store(true, std::memory_order_release);
  registration_wakeup_.notify();
}

// ---- registration thread ----------------------------------------------------------

std::optional<double> Pipeline::newest_trajectory_time() const {
  const std::uint64_t published = trajectory_.published();
  TrajectoryRecord newest;
  if (published == 0 || !trajectory_.read(published - 1, newest)) return std::nullopt;
  return newest.t_s;
}

bool Pipeline::trajectory_may_still_come(std::int64_t scan_complete_steady_ns, double scan_end_s) const {
  if (!parts_.fuser || fuser_finished_.load(std::memory_order_acquire)) return false;
  if (registration_stop_.load(std::memory_order_acquire) == 2) return false;
  if (policy_ == OverflowPolicy::Wait) {
    if (fuser_past_scan_end_s_.load(std::memory_order_acquire) == scan_end_s) return false;
    // Replay: more IMU data can reach the fuser unless the IMU input ended or
    // the io thread is blocked on the full lidar ring (which only this thread
    // empties, so that state holds while we wait) - and the fuser has
    // processed all the io thread delivered.
    const bool io_blocked = io_blocked_on_lidar_.load(std::memory_order_acquire) && lidar_.full();
    const bool io_cannot_deliver = imu_input_ended_.load(std::memory_order_acquire) || io_blocked;
    const bool fuser_done =
        counters_.imu_samples.load(std::memory_order_acquire) == static_cast<std::int64_t>(imu_.pushed());
    return !(io_cannot_deliver && fuser_done);
  }
  // Live: bounded, and not at all while no valid IMU sample comes. Waiting out the
  // bound on every scan of an IMU outage put the registration 0.1 s further
  // behind per scan, and a 2 s unplug overflowed the lidar ring.
  const std::int64_t now = steady_now_ns();
  const std::int64_t last_imu_ns = counters_.last_imu_steady_ns.load(std::memory_order_relaxed);
  return now - scan_complete_steady_ns < trajectory_wait_ns_ && now - last_imu_ns < trajectory_wait_ns_;
}

void Pipeline::run_registration() {
  RegistrationStage& stage = *parts_.registration;
  bool holding = false;
  std::int64_t complete_ns = 0;
  for (;;) {
    registration_heartbeat_.fetch_add(1, std::memory_order_relaxed);
    const int stop = registration_stop_.load(std::memory_order_acquire);
    if (stop == 2) break;
    if (!holding) {
      forward_health_ticks();
      double block_end_s = -std::numeric_limits<double>::infinity();
      const bool got = lidar_.pop_with([&](const PointBlock& block) {
        holding = stage.add_points(block);
        const auto points = block.all_points();
        if (!points.empty()) block_end_s = points.back().t_s;
      });
      if (!got) {
        if (sensor_time_ && input_ended_.load(std::memory_order_acquire) && lidar_.empty() && ticks_in_.empty() &&
            !pending_tick_ && !health_ticks_complete_.load(std::memory_order_relaxed)) {
          health_ticks_complete_.store(true, std::memory_order_release);
          if (wake_main_) wake_main_();
        }
        if (lidar_input_ended_.load(std::memory_order_acquire) && lidar_.empty() &&
            newest_point_s_.load(std::memory_order_relaxed) != std::numeric_limits<double>::infinity()) {
          newest_point_s_.store(std::numeric_limits<double>::infinity(), std::memory_order_release);
          fuser_wakeup_.notify();
        }
        if (stop == 1) break;  // drained
        const bool lidar_ended = lidar_input_ended_.load(std::memory_order_acquire);
        const bool all_ended = input_ended_.load(std::memory_order_acquire);
        const std::uint64_t ticks = ticks_in_.pushed();
        registration_wakeup_.wait(kIdleWait, [&] {
          return !lidar_.empty() || registration_stop_.load(std::memory_order_acquire) != 0 ||
                 lidar_input_ended_.load(std::memory_order_acquire) != lidar_ended ||
                 input_ended_.load(std::memory_order_acquire) != all_ended || ticks_in_.pushed() != ticks;
        });
        continue;
      }
      stage.report(counters_);
      // The fuser's gate: the held scan's end before the newest point (see fuser_may_add).
      if (holding) held_scan_end_s_.store(stage.held_scan_span().end_s, std::memory_order_release);
      if (block_end_s > newest_point_s_.load(std::memory_order_relaxed))
        newest_point_s_.store(block_end_s, std::memory_order_release);
      lidar_popped_.fetch_add(1, std::memory_order_acq_rel);
      fuser_wakeup_.notify();
      if (!holding) continue;
      complete_ns = steady_now_ns();
    }
    const double scan_end_s = stage.held_scan_span().end_s;
    const std::optional<double> newest = newest_trajectory_time();
    // The window must include every correction sent so far (the fuser applies
    // them before its next sample, so this is short): a scan de-skewed and
    // predicted from a trajectory its predecessor has not corrected yet
    // registers worse, and live runs scatter with thread timing. Live, the
    // wait is bounded like the trajectory's.
    const bool corrections_pending =
        corrections_applied_.load(std::memory_order_acquire) < corrections_pushed_ &&
        !fuser_finished_.load(std::memory_order_acquire) &&
        (policy_ == OverflowPolicy::Wait || steady_now_ns() - correction_pushed_steady_ns_ < trajectory_wait_ns_);
    // (Until it initialises, the fuser publishes no trajectory: having passed
    // the scan's end is what counts then.)
    const bool fuser_passed_scan = policy_ == OverflowPolicy::Wait && !newest &&
                                   fuser_time_s_.load(std::memory_order_acquire) >= scan_end_s;
    const bool trajectory_short = !fuser_passed_scan && (!newest || *newest < scan_end_s);
    const bool wait = policy_ == OverflowPolicy::Wait
                          ? (corrections_pending || trajectory_short) && trajectory_may_still_come(complete_ns, scan_end_s)
                          : corrections_pending ||
                                (trajectory_short && trajectory_may_still_come(complete_ns, scan_end_s));
    if (wait) {
      const std::uint64_t published = trajectory_.published();
      const std::int64_t consumed = counters_.imu_samples.load(std::memory_order_acquire);
      const bool io_blocked = io_blocked_on_lidar_.load(std::memory_order_acquire);
      const bool imu_ended = imu_input_ended_.load(std::memory_order_acquire);
      const std::uint64_t applied = corrections_applied_.load(std::memory_order_acquire);
      const double fuser_past = fuser_past_scan_end_s_.load(std::memory_order_acquire);
      registration_wakeup_.wait(kIdleWait, [&] {  // until something that decides the wait changes
        return trajectory_.published() != published ||
               fuser_past_scan_end_s_.load(std::memory_order_acquire) != fuser_past ||
               corrections_applied_.load(std::memory_order_acquire) != applied ||
               counters_.imu_samples.load(std::memory_order_acquire) != consumed ||
               io_blocked_on_lidar_.load(std::memory_order_acquire) != io_blocked ||
               imu_input_ended_.load(std::memory_order_acquire) != imu_ended ||
               fuser_finished_.load(std::memory_order_acquire) ||
               registration_stop_.load(std::memory_order_acquire) != 0;
      });
      continue;
    }
    register_scan(complete_ns);
    holding = false;
    held_scan_end_s_.store(std::numeric_limits<double>::infinity(), std::memory_order_release);
    fuser_wakeup_.notify();
  }
}

void Pipeline::register_scan(std::int64_t scan_complete_steady_ns) {
  RegistrationStage& stage = *parts_.registration;
  const RegistrationStage::TimeSpan span = stage.held_scan_span();
  if (trajectory_.published() == 0) {  // the fuser has not initialised: nothing to place the scan with
    stage.discard_held_scan();
    return;
  }
  WindowRead window = read_window(trajectory_, span.start_s, span.end_s, window_);
  if (window.status == WindowStatus::NotYetReached) {
    // No more waiting: register with the trajectory there is.
    counters_.scans_short_trajectory.fetch_add(1, std::memory_order_relaxed);
    const std::optional<double> newest = newest_trajectory_time();
    window = newest ? read_window(trajectory_, span.start_s, *newest, window_) : WindowRead{WindowStatus::Ok, 0};
  }
  if (window.status != WindowStatus::Ok) {  // overwritten: this thread fell too far behind
    stage.discard_held_scan();
    counters_.scans_dropped.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  // The fuser initialised after this scan: nothing to place it with, as when
  // it has not initialised yet. Which of the two it is depends on how far the
  // fuser ran ahead, so registering such a scan would make the first
  // registered scan, and every pose after it, depend on thread timing.
  if (window.count == 0 || window_[0].t_s >= span.end_s) {
    stage.discard_held_scan();
    return;
  }
  tumble::scan_t* viewer = publish_scan_ ? &scans_.draft() : nullptr;
  stage.register_held_scan(std::span<const TrajectoryRecord>(window_.data(), window.count), registration_out_, viewer);
  registration_out_.scan_complete_steady_ns = scan_complete_steady_ns;
  counters_.scans_registered.fetch_add(1, std::memory_order_relaxed);
  push(corrections_, registration_out_);
  ++corrections_pushed_;
  correction_pushed_steady_ns_ = steady_now_ns();
  fuser_wakeup_.notify();
  push(registrations_, registration_out_);
  counters_.resets.store(registration_out_.resets, std::memory_order_relaxed);
  if (registration_out_.imu_bridged) counters_.scans_imu_bridged.fetch_add(1, std::memory_order_relaxed);
  if (registration_out_.untrusted) counters_.scans_untrusted.fetch_add(1, std::memory_order_relaxed);
  if (registration_out_.jumped) counters_.scans_jumped.fetch_add(1, std::memory_order_relaxed);
  if (registration_out_.awaiting_rest) counters_.scans_awaiting_rest.fetch_add(1, std::memory_order_relaxed);
  if (registration_out_.map_deferred) {
    counters_.scans_map_deferred.fetch_add(1, std::memory_order_relaxed);
  } else if (registration_out_.spin_rate_unmeasured) {  // counted among the registered
    counters_.scans_spin_rate_unmeasured.fetch_add(1, std::memory_order_relaxed);
  }
  if (weakly_constrained(registration_out_, max_expected_error_m_))
    counters_.scans_weakly_constrained.fetch_add(1, std::memory_order_relaxed);
  // Statistics: live, dropping the oldest is fine; on sensor time they decide the health machine.
  if (sensor_time_) {
    push_health(scan_reports_, registration_out_);
  } else {
    scan_reports_.push(registration_out_);
  }
  if (viewer != nullptr) scans_.publish();
  // On data time, so a replay at any rate sends the map as often per scan.
  if (publish_map_period_s_ > 0 && registration_out_.t_s >= next_map_t_s_) {
    stage.fill_viewer_map(maps_.draft());
    maps_.publish();
    next_map_t_s_ = registration_out_.t_s + publish_map_period_s_;
  }
  output_wakeup_.notify();
}

void Pipeline::forward_health_ticks() {
  if (!sensor_time_) return;
  for (;;) {
    if (!pending_tick_) {
      SensorTimeTick tick;
      if (!ticks_in_.pop(tick)) return;
      pending_tick_ = tick;
    }
    // Not before this thread took every lidar item pushed before the tick
    // (and, being called only between scans, registered what they completed).
    if (pending_tick_->lidar_items > lidar_popped_.load(std::memory_order_relaxed) + lidar_.dropped()) return;
    pending_tick_->scan_reports = scan_reports_.pushed();
    push_health(health_ticks_, *pending_tick_);
    pending_tick_.reset();
    if (wake_main_) wake_main_();
  }
}

template <class T>
void Pipeline::push_health(SpscRing<T>& ring, const T& item) {
  while (ring.full() && !health_unwatched_.load(std::memory_order_acquire) &&
         !abandon_.load(std::memory_order_acquire))
    std::this_thread::sleep_for(kRoomPoll);
  ring.push(item);
}

// ---- lifecycle --------------------------------------------------------------------

void Pipeline::stop(Drain drain) {
  const int level = drain == Drain::Yes ? 1 : 2;
  if (drain == Drain::No) abandon_.store(true, std::memory_order_release);
  if (io_thread_.joinable()) {
    boost::asio::post(io_, [this] {
      if (parts_.lidar_source) parts_.lidar_source->stop();
      if (parts_.imu_source) parts_.imu_source->stop();
      io_heartbeat_timer_->cancel();
      io_work_.reset();
      io_.stop();
    });
    io_thread_.join();
  }
  // Fuser before registration: in a drain, registration sees the whole trajectory.
  fuser_stop_.store(level, std::memory_order_release);
  fuser_wakeup_.notify();
  if (fuser_thread_.joinable()) fuser_thread_.join();
  registration_stop_.store(level, std::memory_order_release);
  registration_wakeup_.notify();
  if (registration_thread_.joinable()) registration_thread_.join();
  if (parts_.recorder) parts_.recorder->flush();
}

bool Pipeline::threads_alive() {
  bool alive = true;
  const auto check = [&alive](const std::thread& thread, const std::atomic<std::uint64_t>& heartbeat,
                              std::uint64_t& seen) {
    if (!thread.joinable()) return;
    const std::uint64_t now = heartbeat.load(std::memory_order_relaxed);
    if (now == seen) alive = false;
    seen = now;
  };
  check(io_thread_, io_heartbeat_, seen_io_heartbeat_);
  check(fuser_thread_, fuser_heartbeat_, seen_fuser_heartbeat_);
  check(registration_thread_, registration_heartbeat_, seen_registration_heartbeat_);
  return alive;
}

}  // namespace tumble::daemon
