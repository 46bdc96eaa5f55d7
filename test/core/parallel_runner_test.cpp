#include "core/parallel_runner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "test/core/room_drive.hpp"

namespace tumble {
namespace {

TEST(RangeTask, CallsTheReferencedCallableWithItsArguments) {
  std::vector<std::size_t> seen;
  auto body = [&](std::size_t worker, std::size_t begin, std::size_t end) { seen = {worker, begin, end}; };
  const RangeTask task(body);
  task(2, 5, 9);
  EXPECT_EQ(seen, (std::vector<std::size_t>{2, 5, 9}));
}

TEST(SerialRunner, RunsTheWholeRangeAsWorkerZeroAndNothingForAnEmptyOne) {
  std::vector<std::vector<std::size_t>> calls;
  SerialRunner runner;
  EXPECT_EQ(runner.workers(), 1u);
  runner.run(0, [&](std::size_t w, std::size_t b, std::size_t e) { calls.push_back({w, b, e}); });
  EXPECT_TRUE(calls.empty());
  runner.run(7, [&](std::size_t w, std::size_t b, std::size_t e) { calls.push_back({w, b, e}); });
  EXPECT_EQ(calls, (std::vector<std::vector<std::size_t>>{{0, 0, 7}}));
}

// Splits a loop into ranges of 3, runs them last first and deals them out to
// four worker numbers in turn: the order a pool of threads may well take.
class ScrambledRunner final : public ParallelRunner {
 public:
  std::size_t workers() const override { return 4; }
  void run(std::size_t n, RangeTask task) override {
    std::size_t worker = 0;
    for (std::size_t end = n; end > 0;) {
      const std::size_t begin = end > 3 ? end - 3 : 0;
      task(worker, begin, end);
      worker = (worker + 1) % workers();
      end = begin;
    }
    ++loops;
  }
  std::size_t loops = 0;
};

// What makes a pool of threads deterministic (daemon/worker_pool.hpp): the
// registration's loops give the same result however they are split, ordered
// and assigned to workers.
TEST(ScanRegistration, GivesTheSameResultForAnySplitOfItsLoops) {
  const test::YawAndDrive motion;
  OdometryParams params;
  params.fuser.static_duration_s = 0.3;
  test::RingLidar lidar;
  lidar.columns = test::full_or_coarse(600, 120);
  const double duration_s = test::full_or_coarse(1.2, 0.8);
  const std::vector<ScanResult> serial = test::register_room_drive(motion, params, duration_s, lidar);
  ScrambledRunner scrambled;
  const std::vector<ScanResult> split = test::register_room_drive(motion, params, duration_s, lidar, scrambled);
  EXPECT_GT(scrambled.loops, 0u);
  test::expect_same_results(serial, split);
}

}  // namespace
}  // namespace tumble
