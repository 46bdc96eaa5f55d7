#include "daemon/worker_pool.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace tumble::daemon {

namespace {
// Chunks per worker in one loop: enough to even out uneven points, few
// enough that taking a chunk stays cheap against fitting it.
constexpr std::size_t kChunksPerWorker = 8;
constexpr std::size_t kMinChunk = 16;
}  // namespace

WorkerPool::WorkerPool(std::size_t threads, std::function<void(std::size_t)> on_helper_start) : errors_(threads) {
  if (threads < 1) throw std::invalid_argument("WorkerPool needs at least 1 thread, got 0");
  helpers_.reserve(threads - 1);
  for (std::size_t worker = 1; worker < threads; ++worker)
    helpers_.emplace_back([this, worker, on_helper_start] { helper_loop(worker, on_helper_start); });
}

WorkerPool::~WorkerPool() {
  stopping_.store(true, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (std::thread& helper : helpers_) helper.join();
}

void WorkerPool::helper_loop(std::size_t worker, std::function<void(std::size_t)> on_start) {
  if (on_start) on_start(worker);
  std::uint32_t seen = 0;
  while (true) {
    generation_.wait(seen, std::memory_order_acquire);
    seen = generation_.load(std::memory_order_acquire);
    if (stopping_.load(std::memory_order_relaxed)) return;
    work(worker);
    if (busy_helpers_.fetch_sub(1, std::memory_order_acq_rel) == 1) busy_helpers_.notify_one();
  }
}

void WorkerPool::work(std::size_t worker) {
  try {
    while (true) {
      const std::size_t begin = next_.fetch_add(chunk_, std::memory_order_relaxed);
      if (begin >= n_) return;
      (*task_)(worker, begin, std::min(begin + chunk_, n_));
    }
  } catch (...) {
    errors_[worker] = std::current_exception();
    next_.store(n_, std::memory_order_relaxed);  // the others stop at their next chunk
  }
}

void WorkerPool::run(std::size_t n, RangeTask task) {
  if (n == 0) return;
  if (helpers_.empty() || n < 2 * kMinChunk) {
    task(0, 0, n);
    return;
  }
  task_ = &task;
  n_ = n;
  chunk_ = std::max(kMinChunk, n / (workers() * kChunksPerWorker));
  next_.store(0, std::memory_order_relaxed);
  busy_helpers_.store(static_cast<std::uint32_t>(helpers_.size()), std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  work(0);
  for (std::uint32_t busy = busy_helpers_.load(std::memory_order_acquire); busy != 0;
       busy = busy_helpers_.load(std::memory_order_acquire))
    busy_helpers_.wait(busy, std::memory_order_acquire);
  task_ = nullptr;
  for (std::exception_ptr& error : errors_) {
    if (!error) continue;
    std::exception_ptr first = std::exchange(error, nullptr);
    for (std::exception_ptr& other : errors_) other = nullptr;
    std::rethrow_exception(first);
  }
}

}  // namespace tumble::daemon
