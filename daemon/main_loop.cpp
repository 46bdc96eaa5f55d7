#include "daemon/main_loop.hpp"

#include <poll.h>
#include <signal.h>
#include <sys/eventfd.h>
#include <sys/signalfd.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <system_error>

namespace tumble::daemon {

namespace {

[[noreturn]] void throw_errno(const char* what) { throw std::system_error(errno, std::generic_category(), what); }

sigset_t shutdown_set() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

}  // namespace

ShutdownSignals::ShutdownSignals() {
  const sigset_t set = shutdown_set();
  if (const int error = pthread_sigmask(SIG_BLOCK, &set, &old_mask_); error != 0)
    throw std::system_error(error, std::generic_category(), "pthread_sigmask");
  fd_ = ::signalfd(-1, &set, SFD_NONBLOCK | SFD_CLOEXEC);
  if (fd_ < 0) {
    const int error = errno;
    pthread_sigmask(SIG_SETMASK, &old_mask_, nullptr);
    throw std::system_error(error, std::generic_category(), "signalfd");
  }
}

ShutdownSignals::~ShutdownSignals() {
  ::close(fd_);
  pthread_sigmask(SIG_SETMASK, &old_mask_, nullptr);
}

int ShutdownSignals::take() {
  signalfd_siginfo info{};
  if (::read(fd_, &info, sizeof info) != static_cast<ssize_t>(sizeof info)) return 0;
  return static_cast<int>(info.ssi_signo);
}

MainLoop::MainLoop(ShutdownSignals& signals, std::chrono::nanoseconds tick_period) : signals_(signals) {
  timer_fd_ = ::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
  if (timer_fd_ < 0) throw_errno("timerfd_create");
  wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) {
    ::close(timer_fd_);
    throw_errno("eventfd");
  }
  itimerspec spec{};
  const auto ns = tick_period.count();
  spec.it_interval.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
  spec.it_interval.tv_nsec = static_cast<long>(ns % 1'000'000'000);
  spec.it_value = spec.it_interval;
  if (::timerfd_settime(timer_fd_, 0, &spec, nullptr) != 0) {
    ::close(timer_fd_);
    ::close(wake_fd_);
    throw_errno("timerfd_settime");
  }
}

MainLoop::~MainLoop() {
  ::close(timer_fd_);
  ::close(wake_fd_);
}

MainLoop::Event MainLoop::wait() {
  for (;;) {
    pollfd fds[3] = {{signals_.fd(), POLLIN, 0}, {timer_fd_, POLLIN, 0}, {wake_fd_, POLLIN, 0}};
    if (::poll(fds, 3, -1) < 0) {
      if (errno == EINTR) continue;
      throw_errno("poll");
    }
    if (fds[0].revents & POLLIN) {
      if (const int signal = signals_.take(); signal != 0) {
        last_signal_ = signal;
        return Event::Signal;
      }
    }
    std::uint64_t count = 0;
    if ((fds[1].revents & POLLIN) && ::read(timer_fd_, &count, sizeof count) == sizeof count) return Event::Tick;
    if ((fds[2].revents & POLLIN) && ::read(wake_fd_, &count, sizeof count) == sizeof count) return Event::Woken;
  }
}

void MainLoop::wake() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = ::write(wake_fd_, &one, sizeof one);
}

}  // namespace tumble::daemon
