// The lock-free queues under real concurrency (run under ThreadSanitizer by
// `./tumble test`). Bounded item counts, no sleeps.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <thread>
#include <vector>

#include "daemon/mailbox.hpp"
#include "daemon/spsc_ring.hpp"
#include "daemon/trajectory_buffer.hpp"
#include "daemon/wakeup.hpp"

namespace tumble::daemon {
namespace {

// An item whose fields all derive from its sequence number, so a torn or
// mixed-up copy is detectable.
struct Item {
  std::uint64_t seq = 0;
  std::array<std::uint64_t, 6> words{};
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  static Item make(std::uint64_t seq) {
    Item item;
    item.seq = seq;
    for (std::size_t i = 0; i < item.words.size(); ++i) item.words[i] = seq * (i + 3);
    item.v = Eigen::Vector3d(double(seq), -double(seq), 0.5 * double(seq));
    return item;
  }
  bool consistent() const {
    for (std::size_t i = 0; i < words.size(); ++i)
      if (words[i] != seq * (i + 3)) return false;
    return v == Eigen::Vector3d(double(seq), -double(seq), 0.5 * double(seq));
  }
};

TEST(RingStress, DropOldestUnderContentionKeepsOrderAndCountsEveryItem) {
  constexpr std::uint64_t kItems = 200'000;
  SpscRing<Item> ring(16);
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kItems; ++i) ring.push(Item::make(i));
    done.store(true, std::memory_order_release);
  });
  std::uint64_t popped = 0, inconsistent = 0, out_of_order = 0;
  std::int64_t last = -1;
  Item item;
  for (;;) {
    const bool finished = done.load(std::memory_order_acquire);
    bool any = false;
    while (ring.pop(item)) {
      any = true;
      ++popped;
      if (!item.consistent()) ++inconsistent;
      if (static_cast<std::int64_t>(item.seq) <= last) ++out_of_order;
      last = static_cast<std::int64_t>(item.seq);
    }
    if (finished) break;
    if (!any) std::this_thread::yield();
  }
  producer.join();
  EXPECT_EQ(inconsistent, 0u);
  EXPECT_EQ(out_of_order, 0u);
  EXPECT_EQ(last, static_cast<std::int64_t>(kItems - 1));  // the newest item always survives
  EXPECT_EQ(popped + ring.dropped(), kItems);
  EXPECT_EQ(ring.pushed(), kItems);
  EXPECT_TRUE(ring.empty());
}

TEST(RingStress, TryPushLosesNothing) {
  constexpr std::uint64_t kItems = 20'000;
  SpscRing<Item> ring(8);
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kItems; ++i)
      while (!ring.try_push(Item::make(i))) std::this_thread::yield();
  });
  std::uint64_t expected = 0, bad = 0;
  Item item;
  while (expected < kItems) {
    if (!ring.pop(item)) {
      std::this_thread::yield();
      continue;
    }
    if (item.seq != expected || !item.consistent()) ++bad;
    expected = item.seq + 1;
  }
  producer.join();
  EXPECT_EQ(bad, 0u);
  EXPECT_EQ(ring.dropped(), 0u);
}

TEST(RingStress, WakeupNeverLosesANotification) {
  // Strict ping-pong: every round needs one wake-up on each side. A lost
  // notification would stall a round for the hour-long timeout (the test
  // then fails on ctest's timeout).
  constexpr int kRounds = 2000;
  SpscRing<int> ping(1), pong(1);
  Wakeup ping_wakeup, pong_wakeup;
  std::thread echo([&] {
    int value = 0;
    for (int round = 0; round < kRounds; ++round) {
      while (!ping.pop(value)) ping_wakeup.wait(std::chrono::hours(1), [&] { return !ping.empty(); });
      pong.push(value + 1);
      pong_wakeup.notify();
    }
  });
  int value = 0, wrong = 0;
  for (int round = 0; round < kRounds; ++round) {
    ping.push(round);
    ping_wakeup.notify();
    while (!pong.pop(value)) pong_wakeup.wait(std::chrono::hours(1), [&] { return !pong.empty(); });
    if (value != round + 1) ++wrong;
  }
  echo.join();
  EXPECT_EQ(wrong, 0);
}

TEST(RingStress, MailboxReaderSeesWholeValuesInOrder) {
  constexpr int kValues = 50'000;
  Mailbox<Item> box;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (int i = 1; i <= kValues; ++i) {
      box.draft() = Item::make(static_cast<std::uint64_t>(i));
      box.publish();
    }
    done.store(true, std::memory_order_release);
  });
  std::uint64_t last = 0, bad = 0;
  for (;;) {
    const bool finished = done.load(std::memory_order_acquire);
    while (const Item* item = box.take()) {
      if (!item->consistent() || item->seq <= last) ++bad;
      last = item->seq;
    }
    if (finished) break;
  }
  writer.join();
  EXPECT_EQ(bad, 0u);
  EXPECT_EQ(last, static_cast<std::uint64_t>(kValues));
}

TrajectoryRecord sample(std::uint64_t i) {
  TrajectoryRecord r;
  r.t_s = 0.001 * static_cast<double>(i);
  r.p_w_m = {double(i), 2.0 * double(i), 3.0 * double(i)};
  r.v_w_m_s = {-double(i), 0.0, 1.0};
  r.gyro_saturated_axes = static_cast<std::uint8_t>(i & 7);
  return r;
}

bool consistent(const TrajectoryRecord& r) {
  const double i = r.p_w_m[0];
  return r.p_w_m[1] == 2.0 * i && r.p_w_m[2] == 3.0 * i && r.v_w_m_s[0] == -i && r.t_s == 0.001 * i &&
         r.gyro_saturated_axes == (static_cast<std::uint64_t>(i) & 7);
}

TEST(SeqlockStress, ReadersGetConsistentContiguousWindowsWhileTheWriterRuns) {
  // The writer keeps publishing until both readers have made their attempts.
  constexpr int kAttempts = 3000;
  constexpr std::uint64_t kMaxSamples = 100'000'000;  // a bound, never reached in practice
  TrajectoryBuffer buffer(4096);
  std::atomic<int> readers_done{0};
  std::uint64_t written = 0;
  std::thread writer([&] {
    while (readers_done.load(std::memory_order_acquire) < 2 && written < kMaxSamples) buffer.publish(sample(written++));
  });
  const auto reader = [&](std::uint64_t& windows, std::uint64_t& bad) {
    std::vector<TrajectoryRecord> out(4096);
    for (int attempt = 0; attempt < kAttempts; ++attempt) {
      const std::uint64_t n = buffer.published();
      if (n < 100) {
        --attempt;
        std::this_thread::yield();
        continue;
      }
      const double t1 = 0.001 * static_cast<double>(n - 10);
      const double t0 = t1 - 0.05;
      const WindowRead w = read_window(buffer, t0, t1, out);
      if (w.status != WindowStatus::Ok) continue;  // overwritten meanwhile: allowed, never torn
      ++windows;
      for (std::size_t k = 0; k < w.count; ++k) {
        if (!consistent(out[k])) ++bad;
        if (k > 0 && out[k].p_w_m[0] != out[k - 1].p_w_m[0] + 1.0) ++bad;  // contiguous
      }
      if (out[0].t_s > t0 || out[w.count - 1].t_s < t1) ++bad;  // brackets [t0, t1]
    }
    readers_done.fetch_add(1, std::memory_order_release);
  };
  std::uint64_t windows_a = 0, bad_a = 0, windows_b = 0, bad_b = 0;
  std::thread reader_a([&] { reader(windows_a, bad_a); });
  std::thread reader_b([&] { reader(windows_b, bad_b); });
  reader_a.join();
  reader_b.join();
  writer.join();
  EXPECT_EQ(bad_a + bad_b, 0u);
  EXPECT_GT(windows_a + windows_b, 0u);
  // After the writer: the newest window is always readable.
  std::vector<TrajectoryRecord> out(4096);
  const double end_s = 0.001 * static_cast<double>(written - 1);
  const WindowRead w = read_window(buffer, end_s - 0.1, end_s, out);
  ASSERT_EQ(w.status, WindowStatus::Ok);
  EXPECT_LE(out[0].t_s, end_s - 0.1);
  EXPECT_EQ(out[w.count - 1].t_s, end_s);
}

}  // namespace
}  // namespace tumble::daemon
