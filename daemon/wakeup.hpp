// Wakes a consumer thread that sleeps while its rings are empty, without a
// mutex or condition variable: an eventfd, written only when the consumer
// actually sleeps (so a busy pipeline makes no system call per item).
#pragma once

#include <atomic>
#include <chrono>

namespace tumble::daemon {

class Wakeup {
 public:
  Wakeup();  // throws std::system_error when no eventfd can be created
  ~Wakeup();
  Wakeup(const Wakeup&) = delete;
  Wakeup& operator=(const Wakeup&) = delete;

  // Any thread, after publishing data: wakes the waiter if it sleeps. A
  // waiter not asleep yet finds the data through its ready() check instead.
  void notify();

  // The one consumer thread: returns when ready() is true, after a notify(),
  // or after timeout, whichever comes first. ready() is checked after the
  // consumer announced that it sleeps, so a notify() racing with the check is
  // never lost.
  template <class Ready>
  void wait(std::chrono::milliseconds timeout, Ready&& ready) {
    sleeping_.store(true, std::memory_order_seq_cst);
    std::atomic_thread_fence(std::memory_order_seq_cst);
    if (!ready()) sleep(timeout);
    sleeping_.store(false, std::memory_order_relaxed);
    drain();
  }

 private:
  void sleep(std::chrono::milliseconds timeout);
  void drain();

  int fd_;
  std::atomic<bool> sleeping_{false};
};

}  // namespace tumble::daemon
