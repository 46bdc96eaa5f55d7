#include "daemon/trajectory_file.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstring>
#include <system_error>

#include "daemon/steady_time.hpp"
#include "daemon/thread_setup.hpp"

namespace tumble::daemon {

namespace {

double steady_now_s() { return static_cast<double>(steady_now_ns()) * 1e-9; }

}  // namespace

TrajectoryFile::TrajectoryFile(std::string path, double checkpoint_period_s, std::atomic<std::int64_t>& lines_lost)
    : file_(std::move(path)),
      checkpoint_period_s_(checkpoint_period_s),
      lines_lost_(lines_lost),
      queue_(kQueueCapacity),
      log_(1, 10.0),
      writer_([this] { write_until_stopped(); }) {}

TrajectoryFile::~TrajectoryFile() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  if (writer_.joinable()) writer_.join();
}

void TrajectoryFile::on_registration(const RegistrationRecord& r) {
  if (!r.registered) return;
  queue_.push(Pose{r.t_s, r.position_m, r.orientation_wxyz});
}

void TrajectoryFile::write_until_stopped() {
  name_this_thread("tumble-traj");
  const auto period = std::chrono::duration<double>(checkpoint_period_s_);
  std::unique_lock lock(mutex_);
  for (;;) {
    const bool stopping = wake_.wait_for(lock, period, [this] { return stopping_; });
    lock.unlock();
    take_queued();
    checkpoint();
    if (stopping) return;
    lock.lock();
  }
}

void TrajectoryFile::take_queued() {
  Pose p;
  while (queue_.pop(p)) {
    const auto& q = p.orientation_wxyz;
    fmt::format_to(std::back_inserter(pending_), "{:.6f} {:.6f} {:.6f} {:.6f} {:.9f} {:.9f} {:.9f} {:.9f}\n", p.t_s,
                   p.position_m[0], p.position_m[1], p.position_m[2], q[1], q[2], q[3], q[0]);
    ++pending_lines_;
  }
  const std::uint64_t dropped = queue_.dropped();
  if (dropped > queue_dropped_seen_) {
    const auto lost = static_cast<std::int64_t>(dropped - queue_dropped_seen_);
    queue_dropped_seen_ = dropped;
    lost_any_ = true;
    lines_lost_.fetch_add(lost, std::memory_order_relaxed);
    log_.warn("queue", steady_now_s(), "trajectory: {} poses lost: the writer fell {} poses behind ({} lost so far)",
              lost, kQueueCapacity, lines_lost_.load(std::memory_order_relaxed));
  }
}

void TrajectoryFile::checkpoint() {
  if (pending_.empty()) return;
  const int error = file_.append_durably(pending_);
  if (error == 0) {
    checkpoints_.fetch_add(1, std::memory_order_relaxed);
  } else {
    lost_any_ = true;
    lines_lost_.fetch_add(pending_lines_, std::memory_order_relaxed);
    log_.warn("write", steady_now_s(), "trajectory: {} poses lost: writing {}.partial failed: {} ({} lost so far)",
              pending_lines_, file_.path(), std::strerror(error), lines_lost_.load(std::memory_order_relaxed));
  }
  pending_.clear();
  pending_lines_ = 0;
}

bool TrajectoryFile::commit() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  if (writer_.joinable()) writer_.join();
  bool committed = true;
  try {
    file_.commit();
  } catch (const std::system_error& e) {
    spdlog::error("trajectory: {}: {}", file_.path(), e.what());
    committed = false;
  }
  if (lost_any_)
    spdlog::error("trajectory: {} is missing {} poses (write errors or a full disk; warned about above)", file_.path(),
                  lines_lost_.load(std::memory_order_relaxed));
  return committed && !lost_any_;
}

}  // namespace tumble::daemon
