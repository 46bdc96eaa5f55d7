// What moved leaves the map, on a simulated run: the rolling cage
// pulled down the garage's lane by the rope puller walking ahead of it, with
// four walkers crossing. Registered with the ground truth as trajectory (so
// the map is where the truth says), the map at the end must not keep the
// people where they no longer are.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <string>
#include <vector>

#include "core/scan_registration.hpp"
#include "test/core/synthetic_room.hpp"
#include "test/core_sim/simulated_scans.hpp"
#include "tools/sim/scenario.hpp"
#include "tools/sim/sim_run.hpp"

namespace tumble {
namespace {

sim::Scenario cage_among_people() {
  const std::string yaml =
      "scene: garage\n"
      "motion:\n"
      "  type: rolling_cage\n"
      "  origin: {xyz_m: [-7, 0, 0]}\n"
      "  radius_m: 0.3\n"
      "  roll:\n"
      "    - hold_s: 1.0\n"
      "    - ramp: {to_rad_s: 6, peak_rad_s2: 30}\n"
      "    - hold_s: 3.0\n"
      "  seed: 7\n"
      "people:\n"
      "  walkers: {count: 4}\n"
      "  rope_puller: {}\n"
      "seed: 11\n";
  return sim::parse_scenario(YAML::Load(yaml), "people.yaml", sim::sim_data_dir("scenarios"));
}

// Map points on a person where nobody stands any more, per person (walkers
// first, the puller last): inside that person's body (5 cm around it,
// between knee and crown, clear of floor and ceiling) at some scan of the
// run, 20 cm clear of every body over the last 0.6 s, and more than 10 cm
// from every point of the map the same run makes without the people (a
// walker passes close to a pillar).
std::vector<std::size_t> stale_people_points(const sim::SimRun& run, const LocalMap& map,
                                             const std::vector<double>& scan_times_s, const LocalMap& without_people) {
  const sim::People& people = run.people();
  const double epoch_s = test::epoch_s(run);
  const double radius_m = run.scenario().people.radius_m;
  const double t_end_s = scan_times_s.back() - epoch_s;
  std::vector<std::size_t> stale(people.count(), 0);
  map.for_each_point([&](const Eigen::Vector3d& p_w, const MapPoint&) {
    if (p_w.z() < 0.3 || p_w.z() > 1.6) return;
    auto on = [&](std::size_t i, double t_s, double within_m) {
      return (people.position_xy(i, t_s) - p_w.head<2>()).norm() < radius_m + within_m;
    };
    for (double t = t_end_s - 0.6; t <= t_end_s + 0.1; t += 0.02)
      for (std::size_t i = 0; i < people.count(); ++i)
        if (on(i, t, 0.2)) return;
    Neighbour static_point;
    if (without_people.knn(p_w, 0.1, std::span<Neighbour>(&static_point, 1)) > 0) return;
    for (const double t_scan_s : scan_times_s) {
      for (std::size_t i = 0; i < people.count(); ++i) {
        if (on(i, t_scan_s - epoch_s, 0.05)) {
          ++stale[i];
          return;
        }
      }
    }
  });
  return stale;
}

TEST(SeenThroughOnSimulatedRun, PeopleWhoHaveMovedOnAreNotLeftInTheMap) {
  if (test::kCoarseTests) GTEST_SKIP() << "simulating a run takes minutes in unoptimised builds";
  const sim::SimRun run(cage_among_people());
  ASSERT_EQ(run.people().count(), 5u);
  const std::vector<Scan> scans = test::simulate_scans(run);
  ASSERT_GE(scans.size(), 30u);
  std::vector<double> scan_times_s;
  for (const Scan& scan : scans) scan_times_s.push_back(scan.points.front().t_s);
  sim::Scenario nobody = cage_among_people();
  nobody.people = sim::PeopleConfig{};
  const sim::SimRun static_run(nobody);
  OdometryParams keep_all;
  keep_all.seen_through.enabled = false;
  ScanRegistration static_registration(keep_all);
  test::register_with_ground_truth(static_run, test::simulate_scans(static_run), static_registration);

  auto stale_after_run = [&](bool remove_seen_through, std::size_t& removed) {
    OdometryParams params;
    params.seen_through.enabled = remove_seen_through;
    ScanRegistration registration(params);
    removed = 0;
    const test::GroundTruthReplay replay = test::register_with_ground_truth(
        run, scans, registration, [&](const ScanResult& result) { removed += result.map_points_seen_through; });
    EXPECT_EQ(replay.unregistered, 0u);
    return stale_people_points(run, registration.map(), scan_times_s, static_registration.map());
  };
  std::size_t removed_kept = 0, removed = 0;
  const std::vector<std::size_t> kept = stale_after_run(false, removed_kept);
  const std::vector<std::size_t> left = stale_after_run(true, removed);
  EXPECT_EQ(removed_kept, 0u);
  const std::size_t walkers_kept = kept[0] + kept[1] + kept[2] + kept[3];
  const std::size_t walkers_left = left[0] + left[1] + left[2] + left[3];
  std::printf(
      "map points on people who moved on, kept without removal -> with: the 4 walkers %zu -> %zu, "
      "the rope puller %zu -> %zu (%zu points removed over %zu scans)\n",
      walkers_kept, walkers_left, kept[4], left[4], removed, scans.size());
  EXPECT_GT(walkers_kept, 300u);
  EXPECT_GT(kept[4], 300u);
  EXPECT_LT(walkers_left, walkers_kept / 5);
  EXPECT_LT(left[4], kept[4] / 10);
}

}  // namespace
}  // namespace tumble
