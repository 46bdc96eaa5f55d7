// The injector and the RS-16 driver together: a simulated run whose MSOP
// packets were duplicated and swapped with their neighbours (tumble-sim
// faults) gives the driver the clean run's scans, minus only packets whose
// scan had been handed on before they came.
#include <gtest/gtest.h>

#include <vector>

#include "drivers/rs16/driver.hpp"
#include "drivers/rs16/pcap_source.hpp"
#include "test/tools/sim/sensor_test_support.hpp"
#include "tools/sim/fault_injector.hpp"
#include "tools/sim/run_writer.hpp"

namespace tumble::sim {
namespace {

using test::TempDir;

struct Assembled {
  std::vector<std::vector<LidarPoint>> scans;
  rs16::DecoderStats stats;
};

Assembled assemble(const std::filesystem::path& pcap) {
  Assembled out;
  rs16::PcapSource source(pcap.string(), {});
  rs16::Driver driver({}, [&](Scan& scan, const rs16::ScanReport&) { out.scans.push_back(scan.points); });
  while (const auto d = source.next()) driver.on_datagram(*d);
  out.stats = driver.stats();
  return out;
}

TEST(FaultedScans, DuplicatedAndSwappedPacketsGiveTheCleanRunsScans) {
  TempDir dir;
  test::BoxRoom room;
  const auto scene = room.write(dir.path());
  // Three revolutions of a turntable run (rays are slow under ASan).
  const Scenario scenario = parse_scenario(
      YAML::Load("scene: " + scene.string() +
                 "\nmotion: {type: turntable, axis: [0, 0, 1], origin: {xyz_m: [0.5, -0.3, 1.1]},"
                 " mount: {xyz_m: [0.1, 0, 0.2]},"
                 " profile: [{hold_s: 0.01}, {ramp: {to_rad_s: 2, peak_rad_s2: 100}}, {hold_s: 0.3}]}\n"
                 "seed: 5\nimu: {rate_hz: 400, baud: 921600}\n"),
      "turntable.yaml", dir.path());
  write_run(SimRun(scenario), dir.path() / "clean");
  FaultPlan plan;
  plan.dup_lidar = 0.02;
  plan.swap_lidar = 0.02;
  const FaultCounts injected = inject_faults(dir.path() / "clean", dir.path() / "faulted", plan);
  ASSERT_GT(injected.lidar_duplicated, 0u);
  ASSERT_GT(injected.lidar_swapped_pairs, 0u);

  const Assembled clean = assemble(dir.path() / "clean" / kLidarPcapName);
  const Assembled faulted = assemble(dir.path() / "faulted" / kLidarPcapName);
  ASSERT_GE(clean.scans.size(), 3u);
  EXPECT_EQ(faulted.stats.duplicate_packets, injected.lidar_duplicated);
  EXPECT_EQ(faulted.stats.late_packets + faulted.stats.late_packets_dropped, injected.lidar_swapped_pairs);
  EXPECT_EQ(faulted.stats.time_gaps, 0u);
  EXPECT_EQ(faulted.stats.missing_packets, faulted.stats.late_packets_dropped);
  ASSERT_EQ(faulted.scans.size(), clean.scans.size());
  std::size_t differing = 0;
  for (std::size_t s = 0; s < clean.scans.size(); ++s) {
    const auto& a = clean.scans[s];
    const auto& b = faulted.scans[s];
    for (std::size_t i = 1; i < b.size(); ++i) ASSERT_LE(b[i - 1].t_s, b[i].t_s) << "scan " << s << " out of firing order";
    bool same = a.size() == b.size();
    for (std::size_t i = 0; same && i < a.size(); ++i) same = a[i].t_s == b[i].t_s && a[i].x_m == b[i].x_m;
    differing += !same;
  }
  // A packet dropped late changes at most the scan it belonged to and the next.
  EXPECT_LE(differing, 2 * faulted.stats.late_packets_dropped);
}

}  // namespace
}  // namespace tumble::sim
