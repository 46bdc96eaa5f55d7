// The registration thread's helpers: a ParallelRunner (core/parallel_runner.hpp)
// that splits each per-point loop of a scan between the calling thread and
// threads − 1 helper threads started once. A loop is handed out in chunks
// taken from an atomic counter (a fit near the sensor costs a tenth of one far
// away, so fixed halves would leave one thread idle); helpers sleep on a futex
// (std::atomic::wait) between loops, and nothing is allocated per loop.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <thread>
#include <vector>

#include "core/parallel_runner.hpp"

namespace tumble::daemon {

class WorkerPool final : public ParallelRunner {
 public:
  // threads >= 1, the caller of run() included; on_helper_start(helper number,
  // 1-based) runs first on each helper thread (its name, its priority).
  explicit WorkerPool(std::size_t threads, std::function<void(std::size_t)> on_helper_start = {});
  ~WorkerPool() override;
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  std::size_t workers() const override { return helpers_.size() + 1; }
  // An exception thrown by a range stops the loop and is rethrown here, on
  // the caller (when several threw: the lowest-numbered worker's).
  void run(std::size_t n, RangeTask task) override;

 private:
  void helper_loop(std::size_t worker, std::function<void(std::size_t)> on_start);
  void work(std::size_t worker);

  // The loop being run: written by run() before generation_ is bumped.
  const RangeTask* task_ = nullptr;
  std::size_t n_ = 0;
  std::size_t chunk_ = 1;
  std::atomic<std::size_t> next_{0};        // start of the next chunk to take
  std::atomic<std::uint32_t> generation_{0};  // one per loop; helpers wait on it
  std::atomic<std::uint32_t> busy_helpers_{0};  // helpers not done with the current loop
  std::atomic<bool> stopping_{false};
  std::vector<std::exception_ptr> errors_;  // per worker, from the current loop
  std::vector<std::thread> helpers_;
};

}  // namespace tumble::daemon
