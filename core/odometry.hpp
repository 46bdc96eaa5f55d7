// The lidar-inertial odometry pipeline (docs/layout.md, docs/method.md): IMU
// samples drive the fuser; each lidar scan is de-skewed with the fuser's
// trajectory, down-sampled, given normals and weights, registered to the
// rolling local map, fed back to the fuser and inserted into the map.
//
// Scheduling: with wait_for_imu (default) a scan is held until the fuser's
// trajectory reaches the scan's last point time (de-skewing and the weight
// models need the motion over the whole scan); it is then processed inside the
// add_imu() call that covered it. Held scans are kept in a small fixed queue;
// when it is full the oldest is dropped and counted. Without wait_for_imu a scan
// is processed inside add_scan() at once, and the trajectory past its last IMU
// sample is extrapolated with the last velocity and body rate.
// Scans arriving before the fuser has initialised (its static window) are
// dropped and counted; the first scan after that initialises the map at the
// fuser's pose and is not registered.
//
// Core has no clock: per-stage timings come from the clock the caller injects
// (seconds, any monotonic origin); without one they are not measured.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/imu_fuser.hpp"
#include "core/scan_registration.hpp"
#include "core/types.hpp"

namespace tumble {

struct OdometryStats {
  std::uint64_t scans_received = 0;
  std::uint64_t scans_processed = 0;
  std::uint64_t scans_before_init = 0;       // dropped: the fuser was not initialised
  std::uint64_t scans_dropped_pending = 0;   // dropped: the wait queue was full
  std::uint64_t scans_too_small = 0;         // fewer than min_scan_points
  std::uint64_t scans_out_of_order = 0;      // starting before the previous scan: dropped
  std::uint64_t registrations_failed = 0;    // too few matches
  std::uint64_t registrations_degenerate = 0;
};

class Odometry {
 public:
  using Clock = std::function<double()>;
  using ScanCallback = std::function<void(const ScanResult&)>;
  using PoseCallback = std::function<void(const TrajectorySample&)>;

  // Throws std::invalid_argument naming the inconsistent parameter. runner:
  // see ScanRegistration.
  explicit Odometry(const OdometryParams& params, Clock clock = {}, ParallelRunner& runner = serial_runner());

  // Called with every scan result, inside add_imu()/add_scan().
  void set_scan_callback(ScanCallback callback) { on_scan_ = std::move(callback); }
  // Called after every IMU sample once the fuser is initialised, with the
  // newest fused lidar state (the high-rate pose).
  void set_pose_callback(PoseCallback callback) { on_pose_ = std::move(callback); }

  // Both return how many scans were processed during the call.
  std::size_t add_imu(const ImuSample& sample);
  std::size_t add_scan(const Scan& scan);

  const std::optional<ScanResult>& last_result() const { return last_result_; }
  const ImuFuser& fuser() const { return fuser_; }
  const LocalMap& map() const { return registration_.map(); }
  const PointCloud& reading() const { return registration_.reading(); }  // the newest scan's, de-skewed, filtered
  const OdometryStats& stats() const { return stats_; }
  const OdometryParams& params() const { return params_; }

 private:
  bool covered_by_imu(const Scan& scan) const;
  std::size_t process_ready_scans();
  bool process(const Scan& scan);  // false: dropped (counted)
  double now() const { return clock_ ? clock_() : 0.0; }

  OdometryParams params_;
  Clock clock_;
  ScanCallback on_scan_;
  PoseCallback on_pose_;

  ImuFuser fuser_;
  ScanRegistration registration_;

  std::vector<Scan> pending_;  // ring of max_pending_scans, storage reused
  std::size_t pending_head_ = 0;
  std::size_t pending_count_ = 0;
  ScanResult result_;
  std::optional<ScanResult> last_result_;
  OdometryStats stats_;
};

}  // namespace tumble
