// Speed of the registration half of core: each stage on an RS-16-sized scan
// (16 rings x 1800 firings = 28.8k rays) of a furnished room, and the whole
// per-scan pipeline through Odometry (GVTW, de-skew on) in steady state, with
// the heap allocations it makes per scan. Reported, never asserted.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <ctime>
#include <cstdlib>
#include <new>
#include <optional>
#include <vector>

#include "core/icp.hpp"
#include "core/local_map.hpp"
#include "core/normals.hpp"
#include "core/odometry.hpp"
#include "core/voxel_grid.hpp"
#include "daemon/viewer_messages.hpp"
#include "daemon/worker_pool.hpp"
#include "test/core/synthetic_room.hpp"

// Every heap allocation of the process is counted, so a stage's steady-state
// allocations show as a counter.
namespace {
std::atomic<std::size_t> g_allocations{0};
}  // namespace

// GCC pairs the inlined malloc of operator new with the free of operator
// delete and warns; they are the replacement pair, which is the point.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace tumble {
namespace {

constexpr double kGravity = 9.80665;

// The sensor circles the room (1 m radius, 0.5 m/s) while turning at 1 rad/s,
// after a 1 s static start for the fuser and a 1 s smooth ramp up.
struct CircleMotion {
  double radius_m = 1.0;
  double speed_m_s = 0.5;
  double yaw_rate_rad_s = 1.0;
  double t_go_s = 1.0;
  double ramp_s = 1.0;

  // s(τ) = smoothstep of the ramp, its integral from t_go and its derivative.
  double tau(double t) const { return std::clamp((t - t_go_s) / ramp_s, 0.0, 1.0); }
  double s(double t) const { return tau(t) * tau(t) * (3 - 2 * tau(t)); }
  double s_integral(double t) const {
    if (t <= t_go_s) return 0;
    const double x = tau(t);
    return ramp_s * (x * x * x - x * x * x * x / 2) + std::max(0.0, t - t_go_s - ramp_s);
  }
  double s_rate(double t) const {
    const double x = tau(t);
    return (t <= t_go_s || x >= 1) ? 0.0 : 6 * x * (1 - x) / ramp_s;
  }

  Eigen::Isometry3d pose(double t) const {
    const double phase = speed_m_s / radius_m * s_integral(t);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(radius_m * std::sin(phase), radius_m * (1 - std::cos(phase)), 0);
    T.linear() = Eigen::AngleAxisd(yaw_rate_rad_s * s_integral(t), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T;
  }
  ImuSample imu(double t) const {
    const double phase = speed_m_s / radius_m * s_integral(t);
    const double phase_rate = speed_m_s / radius_m * s(t);
    const double phase_accel = speed_m_s / radius_m * s_rate(t);
    const Eigen::Vector3d tangent(std::cos(phase), std::sin(phase), 0), inward(-std::sin(phase), std::cos(phase), 0);
    const Eigen::Vector3d a_w = radius_m * (phase_accel * tangent + phase_rate * phase_rate * inward);
    ImuSample sample;
    sample.t_s = t;
    sample.accel_m_s2 = pose(t).linear().transpose() * (a_w + Eigen::Vector3d(0, 0, kGravity));
    sample.gyro_rad_s = Eigen::Vector3d(0, 0, yaw_rate_rad_s * s(t));
    return sample;
  }
};

const test::Room& room() {
  static const test::Room r = test::make_room();
  return r;
}

PointCloud static_scan_cloud() {
  return test::to_cloud(test::scan_room(room(), [](double) { return Eigen::Isometry3d::Identity(); }, 0.0));
}

void BM_VoxelDownsample5cm(benchmark::State& state) {
  const PointCloud raw = static_scan_cloud();
  VoxelDownsampler grid(0.05);
  PointCloud out;
  grid.apply(raw, out);
  const std::size_t before = g_allocations.load();
  for (auto _ : state) {
    grid.apply(raw, out);
    benchmark::DoNotOptimize(out.points.data());
  }
  state.counters["points_in"] = static_cast<double>(raw.size());
  state.counters["points_out"] = static_cast<double>(out.size());
  state.counters["allocs_per_call"] =
      static_cast<double>(g_allocations.load() - before) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_VoxelDownsample5cm)->Unit(benchmark::kMillisecond);

void BM_ReadingNormalsK15(benchmark::State& state) {
  PointCloud reading;
  VoxelDownsampler(0.05).apply(static_scan_cloud(), reading);
  NormalParams params{.k = 15};
  if (state.range(0) > 0) params.grid_cell_m = 0.01 * static_cast<double>(state.range(0));
  NormalEstimator estimator(params);
  estimator.estimate(reading, Eigen::Vector3d::Zero());
  const std::size_t before = g_allocations.load();
  for (auto _ : state) {
    estimator.estimate(reading, Eigen::Vector3d::Zero());
    benchmark::DoNotOptimize(reading.normals.data());
  }
  state.counters["points"] = static_cast<double>(reading.size());
  state.counters["allocs_per_call"] =
      static_cast<double>(g_allocations.load() - before) / static_cast<double>(state.iterations());
}
// Argument: NormalParams::grid_cell_m in cm; 0: the default.
BENCHMARK(BM_ReadingNormalsK15)->Unit(benchmark::kMillisecond)->ArgName("grid_cell_cm")->Arg(0)->Arg(25);

// A map of three scans around the origin, and a reading 5 cm / 1 deg off.
struct RegistrationSetup {
  LocalMap map;
  PointCloud reading;
  Eigen::Isometry3d guess;
  RegistrationSetup() {
    VoxelDownsampler grid(0.05);
    NormalEstimator normals;
    for (const double x : {0.0, 0.3, 0.6}) {
      const Eigen::Isometry3d T = test::make_pose(Eigen::Vector3d(x, 0.1 * x, 0), 0, 0, x);
      PointCloud scan;
      grid.apply(test::to_cloud(test::scan_room(room(), [&](double) { return T; }, 0.0)), scan);
      normals.estimate(scan, Eigen::Vector3d::Zero());
      map.insert(scan, T);
    }
    grid.apply(static_scan_cloud(), reading);
    normals.estimate(reading, Eigen::Vector3d::Zero());
    guess = test::make_pose(Eigen::Vector3d(0.05, 0.02, 0.0), 0, 0, 1.0 * M_PI / 180);
  }
};

void BM_MapNearestNeighbour(benchmark::State& state) {
  const RegistrationSetup setup;
  std::vector<Neighbour> out(1);
  std::size_t i = 0;
  for (auto _ : state) {
    const Eigen::Vector3d q = setup.guess * setup.reading.points[i];
    benchmark::DoNotOptimize(setup.map.knn(q, 1.0, out));
    i = (i + 1) % setup.reading.size();
  }
  state.counters["map_points"] = static_cast<double>(setup.map.size());
}
BENCHMARK(BM_MapNearestNeighbour);

void BM_IcpAlign(benchmark::State& state) {
  const RegistrationSetup setup;
  Icp icp;
  IcpResult result = icp.align(setup.reading, setup.map, setup.guess);
  const std::size_t before = g_allocations.load();
  for (auto _ : state) {
    result = icp.align(setup.reading, setup.map, setup.guess);
    benchmark::DoNotOptimize(result.T_wl.data());
  }
  state.counters["reading_points"] = static_cast<double>(setup.reading.size());
  state.counters["iterations"] = result.iterations;
  state.counters["searches_per_point"] =
      static_cast<double>(result.neighbour_searches) / static_cast<double>(setup.reading.size());
  state.counters["allocs_per_call"] =
      static_cast<double>(g_allocations.load() - before) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_IcpAlign)->Unit(benchmark::kMillisecond);

// The stages' clock on one thread: this thread's CPU time, so that the
// figures are "on one core" and do not grow when other processes share the
// machine. With helper threads, the time until the scan is done: wall time.
double seconds_now() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
double wall_seconds_now() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// One RS-16 scan per iteration through Odometry::add_imu/add_scan, the sensor
// circling the room; scan generation (ray casting) is not timed. Counters: the
// median per-scan and per-stage times from the injected clock, and heap
// allocations per scan after the first 30 scans (steady state). Arguments:
// OdometryParams::registration_voxel_size_m in cm (-1: the default); threads
// (1: the calling thread, CPU time; more: a daemon WorkerPool, wall time);
// reading normals from the scan's lines (1) or the k nearest (0).
void BM_OdometryScanGVTW(benchmark::State& state) {
  const CircleMotion motion;
  OdometryParams params;
  params.weights.model = WeightModel::GVTW;
  if (state.range(0) >= 0) params.registration_voxel_size_m = 0.01 * static_cast<double>(state.range(0));
  if (state.range(2) != 0) params.reading_normal_source = ReadingNormalSource::kScanLines;
  const auto threads = static_cast<std::size_t>(state.range(1));
  daemon::WorkerPool pool(threads);
  Odometry odometry(params, threads > 1 ? wall_seconds_now : seconds_now, pool);
  std::vector<double> total, deskew, downsample, normals, weights, registration, icp_matching, icp_solve, fuser,
      map_update;
  std::vector<double> iterations, registered_points, inserted_points;
  odometry.set_scan_callback([&](const ScanResult& r) {
    if (r.map_initialised) return;
    icp_matching.push_back(r.timings.icp_matching_s);
    icp_solve.push_back(r.timings.icp_solve_s);
    registered_points.push_back(static_cast<double>(r.points_registered));
    inserted_points.push_back(static_cast<double>(r.map_insert.inserted));
    total.push_back(r.timings.total_s);
    deskew.push_back(r.timings.deskew_s);
    downsample.push_back(r.timings.downsample_s);
    normals.push_back(r.timings.normals_s);
    weights.push_back(r.timings.weights_s);
    registration.push_back(r.timings.registration_s);
    fuser.push_back(r.timings.fuser_correction_s);
    map_update.push_back(r.timings.map_update_s);
    iterations.push_back(r.iterations);
  });
  total.reserve(1 << 16);
  deskew.reserve(1 << 16);
  downsample.reserve(1 << 16);
  normals.reserve(1 << 16);
  weights.reserve(1 << 16);
  registration.reserve(1 << 16);
  fuser.reserve(1 << 16);
  map_update.reserve(1 << 16);
  iterations.reserve(1 << 16);
  icp_matching.reserve(1 << 16);
  icp_solve.reserve(1 << 16);
  registered_points.reserve(1 << 16);
  inserted_points.reserve(1 << 16);

  int imu_index = 0;
  double scan_start = 0;
  std::uint64_t scan_index = 0;
  Scan scan;
  scan.points.reserve(28800);
  std::size_t scans = 0, steady_allocations = 0, steady_scans = 0;
  auto feed_imu_until = [&](double t_end) {
    while (imu_index * 0.01 <= t_end) odometry.add_imu(motion.imu(imu_index++ * 0.01));
  };
  feed_imu_until(motion.t_go_s);  // the fuser's static start
  scan_start = motion.t_go_s;
  for (auto _ : state) {
    state.PauseTiming();
    scan.index = scan_index++;
    scan.points = test::scan_room(room(), [&](double t) { return motion.pose(t); }, scan_start);
    const std::size_t allocations_before = g_allocations.load();
    state.ResumeTiming();
    feed_imu_until(scan_start + 0.1);
    odometry.add_scan(scan);
    state.PauseTiming();
    if (++scans > 30) {
      steady_allocations += g_allocations.load() - allocations_before;
      ++steady_scans;
    }
    scan_start += 0.1;
    state.ResumeTiming();
  }
  auto ms = [](const std::vector<double>& v) { return 1e3 * median(v); };
  state.counters["median_total_ms"] = ms(total);
  state.counters["median_deskew_ms"] = ms(deskew);
  state.counters["median_downsample_ms"] = ms(downsample);
  state.counters["median_normals_ms"] = ms(normals);
  state.counters["median_weights_ms"] = ms(weights);
  state.counters["median_icp_ms"] = ms(registration);
  state.counters["median_icp_match_ms"] = ms(icp_matching);
  state.counters["median_icp_solve_ms"] = ms(icp_solve);
  state.counters["median_registered_points"] = median(registered_points);
  state.counters["median_inserted_points"] = median(inserted_points);
  state.counters["median_fuser_ms"] = ms(fuser);
  state.counters["median_map_ms"] = ms(map_update);
  state.counters["median_icp_iterations"] = median(iterations);
  state.counters["allocs_per_scan_steady"] =
      steady_scans ? static_cast<double>(steady_allocations) / static_cast<double>(steady_scans) : -1.0;
  state.counters["map_points"] = static_cast<double>(odometry.map().size());
}
BENCHMARK(BM_OdometryScanGVTW)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(150)
    ->ArgNames({"registration_voxel_cm", "threads", "scan_lines"})
    ->Args({-1, 1, 0})  // the default, on one core
    ->Args({0, 1, 0})   // every down-sampled point, as the paper
    ->Args({-1, 2, 0})  // tumbled's default on this 2-core machine
    ->Args({-1, 1, 1})  // reading normals from the scan's lines
    ->Args({-1, 2, 1});

// What tumbled adds to the registration path for viewers (lcm.publish_scan,
// lcm.publish_map_period_s): filling the scan message from the registered
// reading and the map message from the local map, after each scan of the
// room circle (the registration itself not timed). Counters: the median
// time of each fill, the points in each message, and heap allocations per
// fill once the messages' vectors have grown (after 30 scans).
void BM_ViewerMessages(benchmark::State& state) {
  const CircleMotion motion;
  OdometryParams params;
  params.weights.model = WeightModel::GVTW;
  daemon::WorkerPool pool(1);
  Odometry odometry(params, seconds_now, pool);
  std::optional<ScanResult> newest;
  odometry.set_scan_callback([&](const ScanResult& r) { newest = r; });
  int imu_index = 0;
  auto feed_imu_until = [&](double t_end) {
    while (imu_index * 0.01 <= t_end) odometry.add_imu(motion.imu(imu_index++ * 0.01));
  };
  feed_imu_until(motion.t_go_s);
  double scan_start = motion.t_go_s;
  std::uint64_t scan_index = 0;
  Scan scan;
  tumble::scan_t scan_message;
  tumble::map_t map_message;
  std::vector<double> scan_ms, map_ms;
  scan_ms.reserve(1 << 12);
  map_ms.reserve(1 << 12);
  std::size_t steady_allocations = 0, steady_fills = 0;
  for (auto _ : state) {
    state.PauseTiming();
    scan.index = scan_index++;
    scan.points = test::scan_room(room(), [&](double t) { return motion.pose(t); }, scan_start);
    feed_imu_until(scan_start + 0.1);
    odometry.add_scan(scan);
    scan_start += 0.1;
    state.ResumeTiming();
    if (!newest) continue;
    const std::size_t allocations_before = g_allocations.load();
    const double t0 = seconds_now();
    daemon::fill_viewer_scan(odometry.reading(), newest->T_wl, newest->t_scan_start_s, newest->scan_index,
                             scan_message);
    const double t1 = seconds_now();
    daemon::fill_viewer_map(odometry.map(), newest->t_scan_start_s, newest->scan_index, 0, map_message);
    const double t2 = seconds_now();
    scan_ms.push_back(1e3 * (t1 - t0));
    map_ms.push_back(1e3 * (t2 - t1));
    if (scan_index > 30) {
      steady_allocations += g_allocations.load() - allocations_before;
      ++steady_fills;
    }
  }
  state.counters["median_scan_fill_ms"] = median(scan_ms);
  state.counters["max_scan_fill_ms"] = scan_ms.empty() ? 0 : *std::max_element(scan_ms.begin(), scan_ms.end());
  state.counters["median_map_fill_ms"] = median(map_ms);
  state.counters["max_map_fill_ms"] = map_ms.empty() ? 0 : *std::max_element(map_ms.begin(), map_ms.end());
  state.counters["scan_points"] = scan_message.num_points;
  state.counters["scan_message_kB"] = scan_message.getEncodedSize() / 1e3;
  state.counters["map_points"] = static_cast<double>(odometry.map().size());
  state.counters["map_message_points"] = map_message.num_points;
  state.counters["map_message_kB"] = map_message.getEncodedSize() / 1e3;
  state.counters["allocs_per_fill_steady"] =
      steady_fills ? static_cast<double>(steady_allocations) / static_cast<double>(steady_fills) : -1.0;
}
BENCHMARK(BM_ViewerMessages)->Unit(benchmark::kMillisecond)->Iterations(150);

}  // namespace
}  // namespace tumble

BENCHMARK_MAIN();
