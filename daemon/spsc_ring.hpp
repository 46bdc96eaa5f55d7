// A fixed-capacity single-producer single-consumer ring that never blocks the
// producer: when the ring is full, a push drops the OLDEST unread item and
// counts it. Items may be any default-constructible, copy-assignable type
// (Eigen members included); nothing is allocated after construction unless
// the item's own copy allocates.
//
// Why not boost::lockfree::spsc_queue: its producer cannot discard the oldest
// item without racing the consumer, which may be reading exactly that slot.
//
// Design (ownership exchange): there are capacity + 2 slots. Each of the
// `capacity` ring cells holds a 64-bit word = (item sequence number << 16 |
// slot index); sequence 0 means "no unread item". The producer owns one spare
// slot, the consumer owns one. To push, the producer fills its spare slot in
// private, then atomically exchanges it into the cell; whatever slot comes
// back becomes its new spare, and if that slot still held an unread item, the
// item was dropped (counted by the producer, exactly once). To pop, the
// consumer compare-exchanges the cell it expects (sequence = its next item)
// against its own spare, and reads the slot it won at leisure. A slot is
// always owned by exactly one party and changes hands only through an
// acquire/release RMW on a cell, so slot contents are never accessed
// concurrently (ThreadSanitizer-clean by construction).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>

namespace tumble::daemon {

// The type-independent part of a ring: fill level and drop count, readable
// from any thread (status reporting lists rings of different item types).
class RingCounters {
 public:
  explicit RingCounters(std::size_t capacity) : capacity_(capacity) {}
  RingCounters(const RingCounters&) = delete;
  RingCounters& operator=(const RingCounters&) = delete;

  std::size_t capacity() const { return capacity_; }

  // Items waiting for the consumer, 0..capacity (a snapshot).
  std::size_t size() const {
    const std::uint64_t head = head_.load(std::memory_order_acquire);  // read first: head <= tail always
    const std::uint64_t tail = tail_.load(std::memory_order_acquire);
    return tail > head ? static_cast<std::size_t>(std::min<std::uint64_t>(tail - head, capacity_)) : 0;
  }
  double fill() const { return static_cast<double>(size()) / static_cast<double>(capacity_); }
  bool empty() const { return size() == 0; }
  // Items ever pushed, and items dropped unread because the ring was full.
  std::uint64_t pushed() const { return tail_.load(std::memory_order_relaxed); }
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 protected:
  const std::size_t capacity_;
  // Separate cache lines: the producer writes tail_ and dropped_, the consumer head_.
  alignas(64) std::atomic<std::uint64_t> tail_{0};  // items pushed
  alignas(64) std::atomic<std::uint64_t> dropped_{0};
  alignas(64) std::atomic<std::uint64_t> head_{0};  // next item the consumer wants
};

template <class T>
class SpscRing : public RingCounters {
 public:
  static constexpr std::size_t kMaxCapacity = (std::size_t{1} << 16) - 2;

  explicit SpscRing(std::size_t capacity)
      : RingCounters(checked(capacity)),
        slots_(std::make_unique<T[]>(capacity + 2)),
        cells_(std::make_unique<std::atomic<std::uint64_t>[]>(capacity)),
        producer_slot_(static_cast<std::uint32_t>(capacity)),
        consumer_slot_(static_cast<std::uint32_t>(capacity + 1)) {
    for (std::size_t i = 0; i < capacity; ++i) cells_[i].store(pack(0, static_cast<std::uint32_t>(i)));
  }

  // --- producer thread only ---

  // Adds a copy of item; when full, drops the oldest unread item.
  void push(const T& item) {
    push_with([&item](T& slot) { slot = item; });
  }

  // Lets the producer write the item in place (no temporary): fill(T&).
  template <class Fill>
  void push_with(Fill&& fill) {
    fill(slots_[producer_slot_]);
    commit();
  }

  // Like push_with, but fill(T&) returns whether there is an item at all
  // (e.g. a decoder that may reject the input); false pushes nothing.
  template <class Fill>
  bool push_if(Fill&& fill) {
    if (!fill(slots_[producer_slot_])) return false;
    commit();
    return true;
  }

  // True when a push now would drop an item (the consumer may free room at any time).
  bool full() const {
    return tail_.load(std::memory_order_relaxed) - head_.load(std::memory_order_acquire) >= capacity_;
  }

  // Adds the item only when there is room; never drops (replay back-pressure).
  bool try_push(const T& item) {
    if (full()) return false;
    push(item);
    return true;
  }

  // --- consumer thread only ---

  // Takes the oldest unread item; false when the ring is empty.
  bool pop(T& out) {
    return pop_with([&out](const T& slot) { out = slot; });
  }

  // Lets the consumer read the item in place: read(const T&). The slot stays
  // the consumer's until its next pop, so read() may take its time.
  template <class Read>
  bool pop_with(Read&& read) {
    std::uint64_t next = head_.load(std::memory_order_relaxed);
    for (;;) {
      const std::uint64_t tail = tail_.load(std::memory_order_acquire);
      if (next == tail) {
        head_.store(next, std::memory_order_release);
        return false;
      }
      if (tail - next > capacity_) next = tail - capacity_;  // overwritten meanwhile (the producer counted them)
      std::atomic<std::uint64_t>& cell = cells_[next % capacity_];
      std::uint64_t word = cell.load(std::memory_order_acquire);
      if (sequence_of(word) == sequence_of(pack(next + 1, 0)) &&
          cell.compare_exchange_strong(word, pack(0, consumer_slot_), std::memory_order_acq_rel,
                                       std::memory_order_acquire)) {
        consumer_slot_ = slot_of(word);
        head_.store(next + 1, std::memory_order_release);
        read(std::as_const(slots_[consumer_slot_]));
        return true;
      }
      ++next;  // the producer replaced this item after we read tail: it was dropped
    }
  }

 private:
  // Publishes the producer's slot as the next item; takes back the cell's old slot.
  void commit() {
    const std::uint64_t item = tail_.load(std::memory_order_relaxed);
    const std::uint64_t previous =
        cells_[item % capacity_].exchange(pack(item + 1, producer_slot_), std::memory_order_acq_rel);
    producer_slot_ = slot_of(previous);
    if (sequence_of(previous) != 0) dropped_.fetch_add(1, std::memory_order_relaxed);
    tail_.store(item + 1, std::memory_order_release);
  }

  static constexpr unsigned kSlotBits = 16;
  static constexpr std::uint64_t kSlotMask = (std::uint64_t{1} << kSlotBits) - 1;

  static std::uint64_t pack(std::uint64_t sequence, std::uint32_t slot) { return sequence << kSlotBits | slot; }
  static std::uint64_t sequence_of(std::uint64_t word) { return word >> kSlotBits; }
  static std::uint32_t slot_of(std::uint64_t word) { return static_cast<std::uint32_t>(word & kSlotMask); }

  static std::size_t checked(std::size_t capacity) {
    if (capacity < 1 || capacity > kMaxCapacity)
      throw std::invalid_argument("SpscRing capacity " + std::to_string(capacity) + " is out of range (1.." +
                                  std::to_string(kMaxCapacity) + ")");
    return capacity;
  }

  std::unique_ptr<T[]> slots_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> cells_;
  std::uint32_t producer_slot_;  // owned by the producer thread
  std::uint32_t consumer_slot_;  // owned by the consumer thread
};

}  // namespace tumble::daemon
