// A single-writer single-reader "latest value" box (a triple buffer): the
// reader always gets the newest complete value, the writer never waits, and
// values the reader had no time to take are replaced (and counted). Used for
// messages where only the newest matters (status, viewer scans). The three
// values are reused, so a T holding vectors stops allocating once each
// buffer has grown to its working size.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

namespace tumble::daemon {

template <class T>
class Mailbox {
 public:
  Mailbox() = default;
  Mailbox(const Mailbox&) = delete;
  Mailbox& operator=(const Mailbox&) = delete;

  // Writer: the value to fill before publish(); it may hold an older value.
  T& draft() { return buffers_[draft_]; }

  // Writer: makes draft() the newest value and hands the writer another buffer.
  void publish() {
    const std::uint8_t previous = middle_.exchange(draft_ | kFresh, std::memory_order_acq_rel);
    draft_ = previous & kIndexMask;
    if (previous & kFresh) replaced_.fetch_add(1, std::memory_order_relaxed);
    published_.fetch_add(1, std::memory_order_relaxed);
  }

  // Reader: the newest value not taken yet, or nullptr. The value is the
  // reader's (it may complete it) until its next take().
  T* take() {
    if (!(middle_.load(std::memory_order_relaxed) & kFresh)) return nullptr;
    const std::uint8_t previous = middle_.exchange(taken_, std::memory_order_acq_rel);
    taken_ = previous & kIndexMask;
    return &buffers_[taken_];
  }

  // Reader: whether take() would return a value.
  bool has_new() const { return (middle_.load(std::memory_order_acquire) & kFresh) != 0; }

  // Any thread.
  std::uint64_t published() const { return published_.load(std::memory_order_relaxed); }
  std::uint64_t replaced() const { return replaced_.load(std::memory_order_relaxed); }

 private:
  static constexpr std::uint8_t kFresh = 4;
  static constexpr std::uint8_t kIndexMask = 3;

  std::array<T, 3> buffers_{};
  std::uint8_t draft_ = 0;               // writer's buffer
  std::atomic<std::uint8_t> middle_{1};  // the exchanged one, with the fresh bit
  std::uint8_t taken_ = 2;               // reader's buffer
  std::atomic<std::uint64_t> published_{0};
  std::atomic<std::uint64_t> replaced_{0};
};

}  // namespace tumble::daemon
