#include "daemon/worker_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/local_map.hpp"
#include "test/core/room_drive.hpp"
#include "test/core/synthetic_room.hpp"

namespace tumble::daemon {
namespace {

TEST(WorkerPool, RunsEveryIndexExactlyOnceOnDistinctWorkers) {
  WorkerPool pool(3);
  ASSERT_EQ(pool.workers(), 3u);
  for (const std::size_t n : {0u, 1u, 31u, 32u, 33u, 100u, 4097u}) {
    for (int repeat = 0; repeat < 20; ++repeat) {
      SCOPED_TRACE(testing::Message() << "n " << n << " repeat " << repeat);
      std::vector<std::atomic<int>> runs(n);
      std::vector<std::atomic<int>> in_use(pool.workers());
      std::atomic<bool> bad_worker{false}, shared_worker{false};
      pool.run(n, [&](std::size_t worker, std::size_t begin, std::size_t end) {
        if (worker >= in_use.size()) {
          bad_worker = true;
          return;
        }
        if (in_use[worker].fetch_add(1) != 0) shared_worker = true;
        for (std::size_t i = begin; i < end; ++i) runs[i].fetch_add(1);
        in_use[worker].fetch_sub(1);
      });
      EXPECT_FALSE(bad_worker);
      EXPECT_FALSE(shared_worker);
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(runs[i].load(), 1) << "index " << i;
    }
  }
}

TEST(WorkerPool, TheHelperTakesPartOfALoop) {
  WorkerPool pool(2);
  // Each range waits (up to 10 s, for a loaded machine) until both workers
  // have taken one: only a helper that never takes part makes it time out.
  std::atomic<unsigned> workers_seen{0};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  pool.run(64, [&](std::size_t worker, std::size_t, std::size_t) {
    workers_seen.fetch_or(1u << worker);
    while (workers_seen.load() != 3u && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
  });
  EXPECT_EQ(workers_seen.load(), 3u);
}

TEST(WorkerPool, HelpersStartOnceEachWithTheirNumber) {
  std::mutex mutex;
  std::multiset<std::size_t> started;
  {
    WorkerPool pool(4, [&](std::size_t helper) {
      const std::lock_guard lock(mutex);
      started.insert(helper);
    });
    pool.run(1000, [](std::size_t, std::size_t, std::size_t) {});  // every helper has started by the end
  }
  EXPECT_EQ(started, (std::multiset<std::size_t>{1, 2, 3}));
}

TEST(WorkerPool, AnExceptionInARangeReachesTheCallerAndThePoolGoesOn) {
  WorkerPool pool(2);
  EXPECT_THROW(pool.run(1000,
                        [](std::size_t, std::size_t begin, std::size_t end) {
                          if (begin <= 500 && 500 < end) throw std::runtime_error("point 500");
                        }),
               std::runtime_error);
  std::atomic<std::size_t> total{0};
  pool.run(1000, [&](std::size_t, std::size_t begin, std::size_t end) { total += end - begin; });
  EXPECT_EQ(total.load(), 1000u);
}

TEST(WorkerPool, OneThreadRunsEverythingOnTheCaller) {
  WorkerPool pool(1);
  EXPECT_EQ(pool.workers(), 1u);
  std::vector<std::size_t> ranges;
  pool.run(500, [&](std::size_t worker, std::size_t begin, std::size_t end) { ranges.insert(ranges.end(), {worker, begin, end}); });
  EXPECT_EQ(ranges, (std::vector<std::size_t>{0, 0, 500}));
  EXPECT_THROW(WorkerPool(0), std::invalid_argument);
}

// ICP fits a map point's normal when it first matches it, from whichever
// worker gets there first, while the others may want the same point: every
// point gets the normal one thread fits, and under ThreadSanitizer no race.
TEST(WorkerPool, MapNormalsFittedOnFirstUseByThreeThreadsMatchOneThread) {
  const test::Room room = test::make_room();
  const PointCloud surfaces = test::sample_room_surfaces(room, test::full_or_coarse(0.1, 0.3));
  LocalMapParams params;
  params.normals.min_other_line_neighbours = 0;  // samples, not a lidar scan
  LocalMap serial_map(params), shared_map(params);
  serial_map.insert(surfaces, Eigen::Isometry3d::Identity());
  shared_map.insert(surfaces, Eigen::Isometry3d::Identity());
  std::vector<std::uint32_t> indices;
  for (const Eigen::Vector3d& q : surfaces.points) {
    Neighbour self;
    if (shared_map.knn(q, 1e-6, std::span<Neighbour>(&self, 1)) == 1) indices.push_back(self.index);
  }
  ASSERT_GT(indices.size(), 100u);

  WorkerPool pool(3);
  struct Scratch {
    std::vector<Neighbour> neighbours;
    MapPoint own_fit;
  };
  std::vector<Scratch> scratch(pool.workers());
  std::vector<MapPoint> seen(3 * indices.size());
  // Each point three times, at nearby positions in the loop: the workers' ranges meet on the same points.
  const auto index_of = [&](std::size_t j) { return indices[(j / 3 + (j % 3) * 7) % indices.size()]; };
  pool.run(seen.size(), [&](std::size_t worker, std::size_t begin, std::size_t end) {
    for (std::size_t j = begin; j < end; ++j)
      seen[j] = shared_map.fitted_point(index_of(j), scratch[worker].neighbours, scratch[worker].own_fit);
  });
  std::vector<Neighbour> neighbours;
  MapPoint own_fit;
  for (std::size_t j = 0; j < seen.size(); ++j) {
    const MapPoint& expected = serial_map.fitted_point(index_of(j), neighbours, own_fit);
    ASSERT_EQ(seen[j].normal_state, kNormalFitted) << j;
    EXPECT_EQ(seen[j].normal_valid, expected.normal_valid) << j;
    EXPECT_EQ(seen[j].normal_w, expected.normal_w) << j;
  }
}

// The registration on the pool's threads: the same result as on one thread
// (so `--rate max` replays stay byte-identical), and under ThreadSanitizer
// no data race in the shared loops.
TEST(WorkerPool, ScanRegistrationOnThreeThreadsMatchesOneThread) {
  for (const ReadingNormalSource source : {ReadingNormalSource::kNearest, ReadingNormalSource::kScanLines}) {
    SCOPED_TRACE(source == ReadingNormalSource::kNearest ? "k nearest" : "scan lines");
    const test::YawAndDrive motion;
    OdometryParams params;
    params.fuser.static_duration_s = 0.3;
    params.reading_normal_source = source;
    test::RingLidar lidar;
    lidar.columns = test::full_or_coarse(600, 120);
    const double duration_s = test::full_or_coarse(1.2, 0.8);
    const std::vector<ScanResult> serial = test::register_room_drive(motion, params, duration_s, lidar);
    WorkerPool pool(3);
    const std::vector<ScanResult> pooled = test::register_room_drive(motion, params, duration_s, lidar, pool);
    test::expect_same_results(serial, pooled);
  }
}

}  // namespace
}  // namespace tumble::daemon
