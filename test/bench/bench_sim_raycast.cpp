// Rays per second of the scene's nearest-hit query, with RS-16-like beams
// (16 elevations from -15 to +15 deg, full azimuth sweep) from a sensor moving
// through each shipped scene. The lidar model needs ~300k rays per simulated
// second, so ~0.3 s of this per second simulated is the budget to beat.
// Also: the cost of one ground-truth motion query (the lidar model may ask
// once per firing).
#include "tools/sim/motion_load.hpp"
#include "tools/sim/scene_load.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace {

using tumble::sim::Scene;

struct Beam {
  Eigen::Vector3d origin, dir;
};

std::vector<Beam> rs16_like_beams(const Eigen::Vector3d& start, const Eigen::Vector3d& travel) {
  std::vector<Beam> beams;
  constexpr int kAzimuths = 2000;  // 0.18 deg at 10 Hz, one revolution
  for (int a = 0; a < kAzimuths; ++a) {
    const double az = 2 * std::numbers::pi * a / kAzimuths;
    const Eigen::Vector3d origin = start + travel * (static_cast<double>(a) / kAzimuths);
    for (int laser = 0; laser < 16; ++laser) {
      const double el = (-15.0 + 2.0 * laser) * std::numbers::pi / 180;
      beams.push_back({origin, Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el))});
    }
  }
  return beams;
}

void cast_beams(benchmark::State& state, const std::string& scene_name, const Eigen::Vector3d& start) {
  const Scene scene = tumble::sim::load_scene(std::string(TUMBLE_SIM_SCENES_DIR) + "/" + scene_name);
  const std::vector<Beam> beams = rs16_like_beams(start, Eigen::Vector3d(0.35, 0.0, 0.0));
  std::size_t hits = 0;
  for (auto _ : state) {
    for (const Beam& b : beams) {
      auto hit = scene.cast(b.origin, b.dir, 150.0);
      hits += hit.has_value();
      benchmark::DoNotOptimize(hit);
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * beams.size()));
  state.counters["primitives"] = static_cast<double>(scene.primitives().size());
  state.counters["hit_fraction"] = static_cast<double>(hits) / static_cast<double>(state.iterations() * beams.size());
}

void BM_RaycastGarage(benchmark::State& state) { cast_beams(state, "garage.yaml", {-5.0, 0.0, 1.0}); }
void BM_RaycastCorridor(benchmark::State& state) { cast_beams(state, "corridor.yaml", {0.0, 0.0, 1.3}); }
void BM_RaycastYard(benchmark::State& state) { cast_beams(state, "yard.yaml", {5.0, 5.0, 1.5}); }

void BM_MotionAtRollingCage(benchmark::State& state) {
  const auto cage = tumble::sim::load_motion_file(std::string(TUMBLE_SIM_SCENES_DIR) + "/../motions/rolling_cage.yaml");
  double t = 0;
  const double dt = cage->duration_s() / 100000;
  for (auto _ : state) {
    benchmark::DoNotOptimize(cage->at(t));
    t = t + dt > cage->duration_s() ? 0 : t + dt;
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_RaycastGarage)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RaycastCorridor)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RaycastYard)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MotionAtRollingCage);

}  // namespace

BENCHMARK_MAIN();
