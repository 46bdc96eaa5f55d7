// Counters the pipeline threads update and the status thread reads once per
// period. Each is an independent statistic, so relaxed atomics suffice; a
// status message is a set of snapshots, not one consistent cut.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

namespace tumble::daemon {

// A sensor-to-host clock mapping as the driver estimates it.
struct ClockEstimate {
  std::atomic<double> offset_s{0.0};  // host - sensor
  std::atomic<double> drift_ppm{0.0};
  std::atomic<double> jitter_s{0.0};
};

struct PipelineCounters {
  // io thread (decoders copy their cumulative counts in)
  std::atomic<std::int64_t> lidar_packets{0};
  std::atomic<std::int64_t> lidar_bad_packets{0};
  std::atomic<std::int64_t> lidar_missing_packets{0};
  std::atomic<std::int64_t> lidar_foreign_packets{0};
  std::atomic<std::int64_t> lidar_difop_ignored{0};  // disagreed with the configuration in use
  std::atomic<double> lidar_foreign_rate_hz{0.0};  // foreign datagrams to the MSOP port, over the last whole second
  std::atomic<std::int64_t> imu_frames{0};
  std::atomic<std::int64_t> imu_bad_frames{0};
  std::atomic<std::int64_t> imu_gaps{0};
  std::atomic<std::int64_t> imu_duplicate_frames{0};
  std::atomic<std::int64_t> imu_out_of_order_frames{0};
  std::atomic<std::int64_t> imu_rejected_samples{0};  // NaN, Inf or beyond the device's range: not fused
  ClockEstimate imu_clock;
  ClockEstimate lidar_clock;
  // Fresh means data, not bytes: foreign datagrams, DIFOP alone, packets
  // without points or serial bytes that decode to no valid sample must not
  // keep a dead sensor alive (0 = never).
  std::atomic<std::int64_t> last_lidar_steady_ns{0};  // arrival of the newest datagram that gave points
  std::atomic<std::int64_t> last_imu_steady_ns{0};    // arrival of the bytes of the newest valid IMU sample

  // fuser thread
  std::atomic<std::int64_t> imu_samples{0};  // consumed by the fuser
  std::array<std::atomic<std::int64_t>, 3> accel_saturated_samples{};
  std::array<std::atomic<std::int64_t>, 3> gyro_saturated_samples{};
  std::atomic<bool> fuser_initialised{false};

  // registration thread
  std::atomic<std::int64_t> scans_registered{0};
  std::atomic<std::int64_t> scans_dropped{0};           // discarded: too far behind
  std::atomic<std::int64_t> scans_short_trajectory{0};  // registered before the trajectory covered them
  std::atomic<std::int64_t> scans_imu_bridged{0};       // registered without IMU coverage
  std::atomic<std::int64_t> scans_untrusted{0};         // too far from the IMU prediction: not used
  std::atomic<std::int64_t> scans_spin_rate_unmeasured{0};  // gyro clipped about the lidar's spin axis
  std::atomic<std::int64_t> scans_map_deferred{0};          // no local map, gyro clipped: not registered
  std::atomic<std::int64_t> scans_jumped{0};                // registered far from the prediction
  std::atomic<std::int64_t> scans_awaiting_rest{0};         // lost, waiting for rest: not registered
  std::atomic<std::int64_t> scans_weakly_constrained{0};    // expected error above daemon.health.max_expected_error_m
  std::atomic<std::int64_t> resets{0};                  // local maps given up
  // (scan assembly, on the registration thread)
  std::atomic<std::int64_t> lidar_duplicate_packets{0};
  std::atomic<std::int64_t> lidar_late_packets{0};
  std::atomic<std::int64_t> lidar_late_packets_dropped{0};
  std::atomic<std::int64_t> scans_short_coverage{0};  // skipped: not a whole revolution
  std::atomic<std::int64_t> scans_cut_at_bound{0};    // skipped: cut at 1.5 revolutions without passing the split

  // output files (their writer threads)
  std::atomic<std::int64_t> trajectory_lines_lost{0};  // --trajectory-out poses not written: I/O error, disk full
  std::atomic<std::int64_t> record_dropped{0};  // record.dir: items not recorded (queue full, paused, write failed)
  std::atomic<std::int64_t> record_errors{0};   // record.dir: failed creates, writes, syncs
  std::atomic<bool> record_paused{false};       // record.dir: below record.min_free_mib or after a failure
};

}  // namespace tumble::daemon
