// --trajectory-out: the registered scan poses in TUM format, one line per
// registered scan: "t x y z qx qy qz qw" (seconds, metres, unit quaternion
// W <- L). Scans the registration could not place are left out.
//
// The publish thread (real-time) only queues each pose in a bounded ring;
// a writer thread at normal priority appends them to PATH.partial and makes
// them durable (fdatasync) every checkpoint period of wall time
// (daemon.checkpoint_period_s), so a power cut loses at most that much: the
// poses of the last period, in PATH.partial. A pose that cannot be written
// (disk full, an I/O error) or that finds the ring full is lost: counted
// (lines_lost, status_t.trajectory_lines_lost) and warned about, at most
// once per 10 s. commit() writes the rest, syncs and renames to PATH.
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "daemon/atomic_file.hpp"
#include "daemon/lcm_publisher.hpp"
#include "daemon/rate_limited_log.hpp"
#include "daemon/spsc_ring.hpp"

namespace tumble::daemon {

class TrajectoryFile : public RegistrationObserver {
 public:
  static constexpr std::size_t kQueueCapacity = 4096;  // 400 s of scans at 10 Hz

  // Throws std::system_error when PATH.partial cannot be created.
  TrajectoryFile(std::string path, double checkpoint_period_s, std::atomic<std::int64_t>& lines_lost);
  ~TrajectoryFile() override;
  TrajectoryFile(const TrajectoryFile&) = delete;
  TrajectoryFile& operator=(const TrajectoryFile&) = delete;

  void on_registration(const RegistrationRecord& registration) override;
  // Stops the writer once it wrote what is queued, then syncs and renames.
  // False, after an error line, when a pose was lost or the file could not
  // be committed.
  bool commit();
  const std::string& path() const { return file_.path(); }
  // Checkpoints that made poses durable so far.
  std::int64_t checkpoints() const { return checkpoints_.load(std::memory_order_relaxed); }

 private:
  struct Pose {
    double t_s = 0.0;
    std::array<double, 3> position_m{};
    std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};
  };

  void write_until_stopped();
  void take_queued();  // writer thread: ring -> pending_
  void checkpoint();   // writer thread: pending_ -> the disk

  AtomicFile file_;
  const double checkpoint_period_s_;
  std::atomic<std::int64_t>& lines_lost_;
  SpscRing<Pose> queue_;
  std::uint64_t queue_dropped_seen_ = 0;
  std::string pending_;
  std::int64_t pending_lines_ = 0;
  std::atomic<std::int64_t> checkpoints_{0};
  bool lost_any_ = false;
  RateLimitedLog log_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread writer_;  // last: starts once everything above exists
};

}  // namespace tumble::daemon
