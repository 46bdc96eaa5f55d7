// Per-scan cost of de-skewing and of the weight models on an RS-16-sized scan
// (16 rings × 1800 azimuths = 28 800 points over 0.1 s) of a box room seen
// while tumbling, and heap allocations per scan once warm (target: 0; global
// operator new is replaced in this binary to count them).
//
//   build/<dir>/test/bench/bench_core_weights --benchmark_repetitions=10 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <numbers>
#include <vector>

#include "core/deskew.hpp"
#include "core/point_weights.hpp"
#include "core/rotation.hpp"
#include "core/trajectory.hpp"

namespace {
std::atomic<std::size_t> g_allocations{0};
}  // namespace

// Not inlined: GCC would otherwise pair the inlined malloc/free with the
// new/delete expressions at the call sites and warn (-Wmismatched-new-delete).
[[gnu::noinline]] void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
// The array forms default to these two, so they are counted too.
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace tumble {
namespace {

constexpr std::size_t kRings = 16;
constexpr std::size_t kAzimuths = 1800;
constexpr double kScanStart = 500.0;

// The lidar tumbling at 8 rad/s while moving at 3 m/s, sampled at 100 Hz.
Trajectory tumbling_trajectory() {
  Trajectory trajectory(256, SpeedUncertaintyParams{});
  const Eigen::Vector3d omega(1.0, 2.0, 7.7), v(3.0, 0.5, 0.1);
  for (int i = -10; i <= 30; ++i) {
    TrajectorySample s;
    s.t_s = kScanStart + 0.01 * i;
    s.q_wl = integrate_body_rate(Eigen::Quaterniond::Identity(), omega, 0.01 * i);
    s.p_w = v * 0.01 * i;
    s.v_w = v;
    s.omega_l = omega;
    trajectory.push_back(s);
  }
  return trajectory;
}

// One RS-16 revolution inside a 20 × 12 × 4 m box centred near the lidar:
// points, firing times, ring ids and the wall normals.
struct BenchScan {
  std::vector<Eigen::Vector3d> points, normals;
  std::vector<double> times, curvatures;
  std::vector<std::uint8_t> rings;
  Scan scan;
};

BenchScan box_room_scan() {
  BenchScan out;
  const Eigen::Vector3d half(10.0, 6.0, 2.0), centre(1.0, -0.5, 0.3);
  for (std::size_t a = 0; a < kAzimuths; ++a) {
    const double azimuth = 2.0 * std::numbers::pi * static_cast<double>(a) / kAzimuths;
    for (std::size_t r = 0; r < kRings; ++r) {
      const double elevation = (-15.0 + 2.0 * static_cast<double>(r)) * std::numbers::pi / 180.0;
      const Eigen::Vector3d d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                              std::sin(elevation));
      // Nearest wall along d from the lidar at the origin.
      double range = 1e9;
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      for (int axis = 0; axis < 3; ++axis) {
        if (d[axis] == 0.0) continue;
        const double wall = centre[axis] + (d[axis] > 0 ? half[axis] : -half[axis]);
        const double hit = wall / d[axis];
        if (hit > 0 && hit < range) {
          range = hit;
          normal = Eigen::Vector3d::Zero();
          normal[axis] = d[axis] > 0 ? -1.0 : 1.0;
        }
      }
      const double t = kScanStart + 0.1 * (static_cast<double>(a) + static_cast<double>(r) / kRings) / kAzimuths;
      out.points.push_back(range * d);
      out.normals.push_back(normal);
      out.times.push_back(t);
      out.curvatures.push_back(0.01);
      out.rings.push_back(static_cast<std::uint8_t>(r));
      LidarPoint point;
      point.t_s = t;
      point.x_m = static_cast<float>(range * d.x());
      point.y_m = static_cast<float>(range * d.y());
      point.z_m = static_cast<float>(range * d.z());
      point.laser = static_cast<std::uint8_t>(r);
      out.scan.points.push_back(point);
    }
  }
  return out;
}

void report_allocations(benchmark::State& state, std::size_t before) {
  state.counters["allocs_per_scan"] = benchmark::Counter(
      static_cast<double>(g_allocations.load() - before) / static_cast<double>(state.iterations()));
  state.counters["points"] = static_cast<double>(kRings * kAzimuths);
}

void run_weights(benchmark::State& state, WeightModel model, double corner_uncertainty_m) {
  const Trajectory trajectory = tumbling_trajectory();
  const BenchScan scan = box_room_scan();
  PointWeightParams params;
  params.model = model;
  params.corner_point_uncertainty_m = corner_uncertainty_m;
  const PointWeightInput input{scan.points, scan.times, scan.normals, scan.curvatures, scan.rings, kScanStart, true};
  std::vector<double> sigma_n(scan.points.size()), sigma_s(scan.points.size()), weights(scan.points.size());
  PointWeightWorkspace workspace;
  compute_point_weights(params, trajectory, input, {sigma_n, sigma_s, weights}, workspace);  // warm the workspace
  const std::size_t before = g_allocations.load();
  for (auto _ : state) {
    compute_point_weights(params, trajectory, input, {sigma_n, sigma_s, weights}, workspace);
    benchmark::DoNotOptimize(sigma_s.data());
    benchmark::ClobberMemory();
  }
  report_allocations(state, before);
}

void BM_WeightsGvtw(benchmark::State& state) { run_weights(state, WeightModel::GVTW, 0.0); }
void BM_WeightsGvtwWithCornerTerm(benchmark::State& state) { run_weights(state, WeightModel::GVTW, 0.1); }
void BM_WeightsVtw(benchmark::State& state) { run_weights(state, WeightModel::VTW, 0.0); }

void BM_DeskewPoints(benchmark::State& state) {
  const Trajectory trajectory = tumbling_trajectory();
  const BenchScan scan = box_room_scan();
  std::vector<Eigen::Vector3d> out(scan.points.size());
  const std::size_t before = g_allocations.load();
  for (auto _ : state) {
    deskew_points(scan.points, scan.times, kScanStart, trajectory, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  report_allocations(state, before);
}

void BM_DeskewScan(benchmark::State& state) {
  const Trajectory trajectory = tumbling_trajectory();
  const BenchScan scan = box_room_scan();
  std::vector<Eigen::Vector3d> out(scan.points.size());
  const std::size_t before = g_allocations.load();
  for (auto _ : state) {
    deskew_scan(scan.scan, trajectory, true, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  report_allocations(state, before);
}

BENCHMARK(BM_WeightsGvtw)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WeightsGvtwWithCornerTerm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WeightsVtw)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DeskewPoints)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DeskewScan)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace tumble

BENCHMARK_MAIN();
