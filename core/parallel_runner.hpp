// How the per-point loops of a scan (reading normals, ICP matching with the
// map normals it fits, the map's insert candidates) may be spread over
// several threads without core owning one: the caller injects a
// ParallelRunner (tumbled: daemon/worker_pool.hpp), core defaults to
// running everything on the calling thread. Every loop given to
// a runner writes only its own points' slots and its worker's scratch, so
// the result does not depend on how the range is split or scheduled.
#pragma once

#include <cstddef>
#include <memory>
#include <type_traits>
#include <utility>

namespace tumble {

// A non-owning reference to a callable task(worker, begin, end): no
// allocation per call, unlike std::function, so a loop can be handed out
// once per scan stage.
class RangeTask {
 public:
  template <class F>
    requires(!std::is_same_v<std::remove_cvref_t<F>, RangeTask>)
  RangeTask(F&& f) noexcept  // NOLINT: implicit, the call site passes a lambda
      : object_(const_cast<void*>(static_cast<const void*>(std::addressof(f)))),
        call_([](void* object, std::size_t worker, std::size_t begin, std::size_t end) {
          (*static_cast<std::remove_reference_t<F>*>(object))(worker, begin, end);
        }) {}

  void operator()(std::size_t worker, std::size_t begin, std::size_t end) const { call_(object_, worker, begin, end); }

 private:
  void* object_;
  void (*call_)(void*, std::size_t, std::size_t, std::size_t);
};

class ParallelRunner {
 public:
  virtual ~ParallelRunner() = default;
  // Threads a run() may use, the caller's included; workers are numbered
  // 0 .. workers() − 1, so per-worker scratch can be sized up front.
  virtual std::size_t workers() const = 0;
  // Calls task(worker, begin, end) over disjoint ranges that cover [0, n)
  // and returns when all of them are done. No two concurrent calls have
  // the same worker number.
  virtual void run(std::size_t n, RangeTask task) = 0;
};

// Everything on the calling thread, in one range.
class SerialRunner final : public ParallelRunner {
 public:
  std::size_t workers() const override { return 1; }
  void run(std::size_t n, RangeTask task) override {
    if (n > 0) task(0, 0, n);
  }
};

// The runner a component uses when it was given none.
inline ParallelRunner& serial_runner() {
  static SerialRunner runner;
  return runner;
}

}  // namespace tumble
