// The pipeline's threads and the queues between them (docs/layout.md):
//
//   io            io_context: sources -> decoders -> imu ring, lidar ring
//   fuser         imu ring + correction ring -> FuserStage -> trajectory buffer + odometry ring
//   registration  lidar ring + trajectory window -> RegistrationStage
//                 -> correction ring, registration ring, scan reports, viewer scans
//
// The publish thread (LcmPublisher) drains the odometry and registration
// rings and the two mailboxes; the main thread drains the scan reports into
// status. Threads start only for the parts that are present.
//
// Live, a full ring drops its oldest item (counted). Replaying at --rate max
// nothing may be dropped and two runs must give the same output, so
// producers wait for room instead (OverflowPolicy::Wait), a complete scan
// waits for the trajectory to cover it until no more IMU data can arrive,
// and the two compute threads keep in step the way a single-threaded
// odometry would: the fuser adds no IMU sample past the end of a complete
// scan whose correction it has not applied, nor one later than the lidar
// data the registration thread has seen (a scan may still end before it).
// Which samples the correction re-propagates, and so every output, is then
// fixed by the data. That assumes the replay sources deliver lidar and IMU
// records merged in record-time order.
#pragma once

#include <atomic>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "daemon/config.hpp"
#include "daemon/lcm_publisher.hpp"
#include "daemon/mailbox.hpp"
#include "daemon/records.hpp"
#include "daemon/seams.hpp"
#include "daemon/spsc_ring.hpp"
#include "daemon/status_aggregator.hpp"
#include "daemon/status_counters.hpp"
#include "daemon/trajectory_buffer.hpp"
#include "daemon/wakeup.hpp"
#include "tumble/map_t.hpp"
#include "tumble/scan_t.hpp"
#include "tumble/status_t.hpp"

namespace tumble::daemon {

struct PipelineParts {
  std::unique_ptr<LidarDatagramSource> lidar_source;  // needs lidar_decoder and registration
  std::unique_ptr<ImuByteSource> imu_source;          // needs imu_decoder and fuser
  std::unique_ptr<LidarDecoder> lidar_decoder;
  std::unique_ptr<ImuDecoder> imu_decoder;
  std::unique_ptr<Recorder> recorder;
  std::unique_ptr<FuserStage> fuser;
  std::unique_ptr<RegistrationStage> registration;
};

enum class HealthClock {
  Steady,  // live: the health machine runs on the main thread's timer
  Sensor,  // replay: on the data's own time (SensorTimeTick every kHealthPeriod_s)
};

enum class OverflowPolicy {
  DropOldest,  // live: never block a producer
  Wait,        // replay at max rate: lose nothing
};

class Pipeline {
 public:
  static constexpr double kHealthPeriod_s = 0.1;  // of sensor time, between health evaluations

  Pipeline(const DaemonConfig& config, OverflowPolicy policy, HealthClock clock = HealthClock::Steady);
  ~Pipeline();  // stop(Drain::No)
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // For sources that need it (live sockets, serial ports, replay timers); valid before start().
  boost::asio::io_context& io_context() { return io_; }

  // Takes the parts and starts the threads they need. wake_main is called
  // (from a pipeline thread) when input_ended() or failure() changes.
  // Throws std::invalid_argument when a source lacks its decoder or stage.
  void start(PipelineParts parts, std::function<void()> wake_main);

  // Every source present reported its end (replay finished).
  bool input_ended() const { return input_ended_.load(std::memory_order_acquire); }
  // A pipeline thread stopped on an exception: its message.
  std::optional<std::string> failure() const;

  enum class Drain {
    No,   // stop now (signal): queued data is dropped
    Yes,  // end of replay: process everything queued first
  };
  // Stops sources, then the threads in data-flow order; flushes the recorder.
  void stop(Drain drain);

  // The queues the publish thread drains and the Wakeup it sleeps on.
  PublisherInputs publisher_inputs();
  Wakeup& output_wakeup() { return output_wakeup_; }
  Mailbox<tumble::status_t>& status_mailbox() { return status_; }
  SpscRing<RegistrationRecord>& scan_reports() { return scan_reports_; }
  // HealthClock::Sensor: the ticks for StatusAggregator::evaluate, in order.
  SpscRing<SensorTimeTick>& health_ticks() { return health_ticks_; }
  // HealthClock::Sensor: the input ended and every tick and scan report is pushed.
  bool health_ticks_complete() const { return health_ticks_complete_.load(std::memory_order_acquire); }
  // The main thread no longer drains the health ticks and scan reports: stop waiting for room in them.
  void stop_reporting_health() { health_unwatched_.store(true, std::memory_order_release); }
  std::vector<NamedRing> rings() const;
  const PipelineCounters& counters() const { return counters_; }
  // For the output files' writers, which count their own failures here.
  PipelineCounters& counters() { return counters_; }

  // True when every running pipeline thread made progress since the previous call.
  bool threads_alive();

 private:
  template <class T>
  void wait_for_room(SpscRing<T>& ring, std::atomic<bool>* blocked);
  template <class T>
  void push(SpscRing<T>& ring, const T& item);
  void fail(std::string message);
  void run_io();
  void on_lidar_datagram(const LidarDatagram& datagram);
  void on_imu_bytes(const ImuBytes& bytes);
  void on_source_end();
  void advance_sensor_time(double t_s);
  void forward_health_ticks();  // registration thread, between scans
  template <class T>
  void push_health(SpscRing<T>& ring, const T& item);
  void run_fuser();
  bool fuser_may_add(double t_s, double previous_t_s) const;
  void run_registration();
  std::optional<double> newest_trajectory_time() const;
  bool trajectory_may_still_come(std::int64_t scan_complete_steady_ns, double scan_end_s) const;
  void register_scan(std::int64_t scan_complete_steady_ns);
  enum class Priority {
    ImuPath,     // daemon.realtime_priority
    Background,  // daemon.registration_nice
  };
  void start_thread(std::thread& thread, const char* name, void (Pipeline::*body)(), Priority priority);
  void beat_io();

  const OverflowPolicy policy_;
  const bool publish_scan_;
  const double publish_map_period_s_;  // 0: no map for viewers
  double next_map_t_s_ = 0.0;          // data time of the next map message (registration thread)
  const int realtime_priority_;
  const int registration_nice_;
  const std::int64_t trajectory_wait_ns_;
  const double trajectory_wait_s_;
  const double max_expected_error_m_;
  const bool sensor_time_;

  // Before parts_: sources built on the io_context must be destroyed before it.
  boost::asio::io_context io_;
  PipelineParts parts_;
  PipelineCounters counters_;

  SpscRing<ImuArrival> imu_;
  SpscRing<PointBlock> lidar_;
  SpscRing<RegistrationRecord> corrections_;
  SpscRing<TrajectoryRecord> odometry_;
  SpscRing<RegistrationRecord> registrations_;
  SpscRing<RegistrationRecord> scan_reports_;
  SpscRing<SensorTimeTick> ticks_in_;      // io -> registration
  SpscRing<SensorTimeTick> health_ticks_;  // registration -> main
  TrajectoryBuffer trajectory_;
  Mailbox<tumble::status_t> status_;
  Mailbox<tumble::scan_t> scans_;
  Mailbox<tumble::map_t> maps_;

  Wakeup fuser_wakeup_;
  Wakeup registration_wakeup_;
  Wakeup output_wakeup_;

  // io thread
  std::optional<boost::asio::executor_work_guard<boost::asio::io_context::executor_type>> io_work_;
  std::function<void(const ImuSample&)> emit_imu_;
  std::int64_t imu_bytes_steady_ns_ = 0;  // io thread: when the bytes being decoded arrived
  double imu_bytes_arrival_s_ = 0.0;      // io thread: their host (replay: record) time
  std::int64_t next_tick_ = -1;           // io thread, HealthClock::Sensor: index of the next tick (-1: no record yet)
  double newest_imu_s_ = -1.0;
  double newest_lidar_s_ = -1.0;
  std::optional<boost::asio::steady_timer> io_heartbeat_timer_;
  int sources_running_ = 0;
  std::atomic<bool> imu_input_ended_{false};
  std::atomic<bool> lidar_input_ended_{false};
  std::atomic<bool> io_blocked_on_lidar_{false};
  std::atomic<bool> io_blocked_on_imu_{false};

  // fuser thread
  std::function<void(const TrajectoryRecord&)> republish_;
  std::atomic<std::uint64_t> corrections_applied_{0};
  std::atomic<double> fuser_time_s_{-std::numeric_limits<double>::infinity()};  // newest sample added

  // registration thread
  std::vector<TrajectoryRecord> window_;  // sized once: the trajectory buffer's capacity
  RegistrationRecord registration_out_;
  std::uint64_t corrections_pushed_ = 0;
  std::int64_t correction_pushed_steady_ns_ = 0;  // registration thread: when the newest was pushed
  std::atomic<std::uint64_t> lidar_popped_{0};  // blocks taken, each after the gate below was updated for it
  std::optional<SensorTimeTick> pending_tick_;
  std::atomic<bool> health_ticks_complete_{false};
  std::atomic<bool> health_unwatched_{false};
  // OverflowPolicy::Wait: the end of the held scan the fuser holds a sample
  // for that came more than trajectory_wait_s after it (an IMU gap): that
  // scan gets no more trajectory, as it would not live.
  std::atomic<double> fuser_past_scan_end_s_{-std::numeric_limits<double>::infinity()};
  // The fuser's step gate (OverflowPolicy::Wait): the end of the complete scan
  // not yet registered (+inf: none), and the newest lidar point seen (+inf: no
  // more lidar data). A point, not a packet: packets without points (the
  // lidar facing the sky) do not move a scan's end, so a scan completed later
  // may end before them.
  std::atomic<double> held_scan_end_s_{std::numeric_limits<double>::infinity()};
  std::atomic<double> newest_point_s_{-std::numeric_limits<double>::infinity()};

  std::function<void()> wake_main_;
  std::atomic<bool> input_ended_{false};
  std::atomic<bool> failing_{false};
  std::atomic<bool> failed_{false};  // failure_ is written before this is set
  std::string failure_;
  std::atomic<bool> abandon_{false};  // stop now: producers stop waiting for room

  // stop requests: 0 running, 1 drain then stop, 2 stop now
  std::atomic<int> fuser_stop_{0};
  std::atomic<int> registration_stop_{0};
  std::atomic<bool> fuser_finished_{false};

  std::thread io_thread_;
  std::thread fuser_thread_;
  std::thread registration_thread_;
  std::atomic<std::uint64_t> io_heartbeat_{0};
  std::atomic<std::uint64_t> fuser_heartbeat_{0};
  std::atomic<std::uint64_t> registration_heartbeat_{0};
  std::uint64_t seen_fuser_heartbeat_ = 0;
  std::uint64_t seen_registration_heartbeat_ = 0;
  std::uint64_t seen_io_heartbeat_ = 0;
};

}  // namespace tumble::daemon
