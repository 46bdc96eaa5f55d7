// The fused trajectory, published by the fuser thread (one writer) and read
// by the registration thread (any number of readers) without locks: a ring of
// seqlock-protected slots. The writer never waits; a reader that raced the
// writer retries or learns that the sample it wanted was overwritten.
//
// Each slot stores its item as atomic 64-bit words, so the concurrent copy is
// not a data race in the C++ memory model (and ThreadSanitizer agrees); the
// fences follow Boehm, "Can seqlocks get along with programming language
// memory models?" (2012). The item must therefore be trivially copyable:
// Eigen types are not, which is why the trajectory travels as a
// TrajectoryRecord of plain arrays.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "daemon/records.hpp"

namespace tumble::daemon {

template <class T>
class SeqlockRing {
  static_assert(std::is_trivially_copyable_v<T>, "SeqlockRing copies items word by word");

 public:
  explicit SeqlockRing(std::size_t capacity) : capacity_(capacity), slots_(std::make_unique<Slot[]>(capacity)) {
    if (capacity < 2) throw std::invalid_argument("SeqlockRing capacity " + std::to_string(capacity) + " < 2");
  }
  SeqlockRing(const SeqlockRing&) = delete;
  SeqlockRing& operator=(const SeqlockRing&) = delete;

  std::size_t capacity() const { return capacity_; }

  // Writer thread only: appends item as number published().
  void publish(const T& item) {
    const std::uint64_t index = published_.load(std::memory_order_relaxed);
    Slot& slot = slots_[index % capacity_];
    Words words{};
    std::memcpy(words.data(), &item, sizeof(T));
    slot.sequence.store(2 * index + 1, std::memory_order_relaxed);  // odd: being written
    std::atomic_thread_fence(std::memory_order_release);
    for (std::size_t i = 0; i < kWords; ++i) slot.words[i].store(words[i], std::memory_order_relaxed);
    slot.sequence.store(2 * index + 2, std::memory_order_release);  // even: holds item `index`
    published_.store(index + 1, std::memory_order_release);
  }

  // Any thread: items published so far (item numbers 0..published()-1).
  std::uint64_t published() const { return published_.load(std::memory_order_acquire); }

  // Any thread: copies item `index`; false when it is not published yet or
  // was overwritten (the ring holds the newest capacity() items).
  bool read(std::uint64_t index, T& out) const {
    if (index >= published()) return false;
    const Slot& slot = slots_[index % capacity_];
    const std::uint64_t before = slot.sequence.load(std::memory_order_acquire);
    if (before != 2 * index + 2) return false;  // a newer item took (or is taking) the slot
    Words words;
    for (std::size_t i = 0; i < kWords; ++i) words[i] = slot.words[i].load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (slot.sequence.load(std::memory_order_relaxed) != before) return false;  // overwritten while copying
    std::memcpy(static_cast<void*>(&out), words.data(), sizeof(T));             // T is trivially copyable
    return true;
  }

 private:
  static constexpr std::size_t kWords = (sizeof(T) + 7) / 8;
  using Words = std::array<std::uint64_t, kWords>;
  struct Slot {
    std::atomic<std::uint64_t> sequence{0};
    std::array<std::atomic<std::uint64_t>, kWords> words{};
  };

  const std::size_t capacity_;
  std::unique_ptr<Slot[]> slots_;
  std::atomic<std::uint64_t> published_{0};
};

using TrajectoryBuffer = SeqlockRing<TrajectoryRecord>;

enum class WindowStatus {
  Ok,             // out[0..count): the first sample is at or before t0 (unless it is the very
                  // first sample ever published), the last one at or after t1
  NotYetReached,  // the newest sample is older than t1: wait for the fuser
  Overwritten,    // samples needed were already overwritten: the buffer is too small for the lag
  TooSmall,       // out cannot hold the window
};

struct WindowRead {
  WindowStatus status = WindowStatus::NotYetReached;
  std::size_t count = 0;
};

// Copies, in time order, the samples that bracket [t0_s, t1_s] into out. Each
// sample is read consistently and published samples never change, so the
// window is consistent as a whole. Never allocates, never blocks the writer.
//
// The fuser republishes the tail it rewrote after a lidar correction, so
// publication order is not time order: a record supersedes every earlier-
// published record at or after its time. Walking back from the newest, a
// record is kept only when it is older than everything kept so far.
inline WindowRead read_window(const TrajectoryBuffer& buffer, double t0_s, double t1_s,
                              std::span<TrajectoryRecord> out) {
  const std::uint64_t published = buffer.published();
  if (published == 0) return {WindowStatus::NotYetReached, 0};
  std::uint64_t index = published - 1;
  TrajectoryRecord sample;
  if (!buffer.read(index, sample)) return {WindowStatus::Overwritten, 0};
  if (sample.t_s < t1_s) return {WindowStatus::NotYetReached, 0};
  std::size_t count = 0;
  for (;;) {
    if (count == 0 || sample.t_s < out[count - 1].t_s) {
      if (count > 0 && sample.t_s >= t1_s) {
        out[count - 1] = sample;  // only the oldest sample at or after t1 is needed
      } else {
        if (count == out.size()) return {WindowStatus::TooSmall, 0};
        out[count++] = sample;
      }
      if (sample.t_s <= t0_s) break;
    }
    if (index == 0) break;
    --index;
    if (!buffer.read(index, sample)) return {WindowStatus::Overwritten, 0};
  }
  for (std::size_t i = 0; i < count / 2; ++i) std::swap(out[i], out[count - 1 - i]);
  return {WindowStatus::Ok, count};
}

}  // namespace tumble::daemon
