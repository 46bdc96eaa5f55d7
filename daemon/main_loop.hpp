// The main thread's wait: SIGINT/SIGTERM through a signalfd, a periodic tick
// through a timerfd, and wake-ups from other threads (end of a replay)
// through an eventfd: one poll(), no signal handler, no lost signal.
#pragma once

#include <signal.h>

#include <chrono>

namespace tumble::daemon {

// Blocks SIGINT and SIGTERM in the calling thread, and therefore in every
// thread it starts afterwards, so they wait in the signalfd for the main
// loop. Construct it in main() before any other thread exists.
class ShutdownSignals {
 public:
  ShutdownSignals();   // throws std::system_error
  ~ShutdownSignals();  // restores the previous signal mask
  ShutdownSignals(const ShutdownSignals&) = delete;
  ShutdownSignals& operator=(const ShutdownSignals&) = delete;

  int fd() const { return fd_; }
  // The number of a pending signal (consuming it), or 0.
  int take();

 private:
  int fd_;
  sigset_t old_mask_;
};

class MainLoop {
 public:
  enum class Event { Tick, Signal, Woken };

  MainLoop(ShutdownSignals& signals, std::chrono::nanoseconds tick_period);  // throws std::system_error
  ~MainLoop();
  MainLoop(const MainLoop&) = delete;
  MainLoop& operator=(const MainLoop&) = delete;

  // Blocks until something happens. A signal wins over a tick or a wake-up.
  Event wait();
  int last_signal() const { return last_signal_; }

  // Any thread: makes wait() return Woken.
  void wake();

 private:
  ShutdownSignals& signals_;
  int timer_fd_;
  int wake_fd_;
  int last_signal_ = 0;
};

}  // namespace tumble::daemon
