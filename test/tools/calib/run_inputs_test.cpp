#include "tools/calib/run_inputs.hpp"

#include <gtest/gtest.h>

#include "test/tools/calib/temp_dir.hpp"
#include "tools/sim/fault_injector.hpp"

namespace tumble::calib {
namespace {

double first_scan_start_s(const std::filesystem::path& pcap, rs16::ClockMode clock) {
  double t_s = 0.0;
  bool first = true;
  for_each_scan(pcap, clock, [&](const Scan& scan) {
    if (first) t_s = scan.points.front().t_s;
    first = false;
  });
  return t_s;
}

// A lidar without PTP or GPS (tumbled's default lidar.clock: free) stamps its
// packets with its own count: read as synced, its scans would sit 100 s away
// from the IMU's samples, and no offset search finds that.
TEST(RunInputs, AFreeLidarClockIsMappedToTheArrivalTimesASyncedOneIsTakenAsIs) {
  TempDir dir;
  test::write_still_garage_run(dir.path() / "synced", 0.5);
  sim::FaultPlan own_clock;
  own_clock.lidar_clock_jump = sim::ClockJump{.at_s = 0.0, .jump_s = 100.0};
  sim::inject_faults(dir.path() / "synced", dir.path() / "free", own_clock);

  const double synced_s = first_scan_start_s(dir.path() / "synced" / "lidar.pcap", rs16::ClockMode::Synced);
  EXPECT_NEAR(first_scan_start_s(dir.path() / "free" / "lidar.pcap", rs16::ClockMode::Synced), synced_s + 100.0, 1e-3);
  EXPECT_NEAR(first_scan_start_s(dir.path() / "free" / "lidar.pcap", rs16::ClockMode::Free), synced_s, 0.01);
}

}  // namespace
}  // namespace tumble::calib
