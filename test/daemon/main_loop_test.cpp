#include "daemon/main_loop.hpp"

#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>

#include <chrono>

namespace tumble::daemon {
namespace {

using namespace std::chrono_literals;

TEST(MainLoop, WakeUpsAndTicks) {
  ShutdownSignals signals;
  MainLoop loop(signals, 1ms);
  loop.wake();
  MainLoop::Event first = loop.wait();
  if (first == MainLoop::Event::Tick) first = loop.wait();  // the timer may fire first
  EXPECT_EQ(first, MainLoop::Event::Woken);
  EXPECT_EQ(loop.wait(), MainLoop::Event::Tick);
}

TEST(MainLoop, SigtermBecomesAnEventNotADeath) {
  ShutdownSignals signals;  // blocks SIGTERM in this thread
  MainLoop loop(signals, 1h);
  ASSERT_EQ(pthread_kill(pthread_self(), SIGTERM), 0);  // pending for this thread, read by the signalfd
  EXPECT_EQ(loop.wait(), MainLoop::Event::Signal);
  EXPECT_EQ(loop.last_signal(), SIGTERM);
  ASSERT_EQ(pthread_kill(pthread_self(), SIGINT), 0);
  EXPECT_EQ(loop.wait(), MainLoop::Event::Signal);
  EXPECT_EQ(loop.last_signal(), SIGINT);
}

TEST(ShutdownSignals, RestoresTheSignalMask) {
  sigset_t before;
  pthread_sigmask(SIG_SETMASK, nullptr, &before);
  { ShutdownSignals signals; }
  sigset_t after;
  pthread_sigmask(SIG_SETMASK, nullptr, &after);
  EXPECT_EQ(sigismember(&before, SIGTERM), sigismember(&after, SIGTERM));
  EXPECT_EQ(sigismember(&before, SIGINT), sigismember(&after, SIGINT));
}

}  // namespace
}  // namespace tumble::daemon
