// Counts heap allocations made by the calling thread, through a replacement
// global operator new (or, under ThreadSanitizer, a sanitizer malloc hook);
// link the tumble_alloc_counter object library. Use it to prove that a
// steady-state path allocates nothing:
//
//   tumble::test::AllocationCounter allocations;
//   ring.push(item);
//   EXPECT_EQ(allocations.count(), 0u);
#pragma once

#include <cstdint>

namespace tumble::test {

// Allocations by this thread since the program started.
std::uint64_t thread_allocations();

class AllocationCounter {
 public:
  AllocationCounter() : start_(thread_allocations()) {}
  // Allocations by this thread since construction (or the last reset()).
  std::uint64_t count() const { return thread_allocations() - start_; }
  void reset() { start_ = thread_allocations(); }

 private:
  std::uint64_t start_;
};

}  // namespace tumble::test
