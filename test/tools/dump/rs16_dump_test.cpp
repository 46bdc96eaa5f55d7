// tumble-dump rs16 on the synthetic RS-16 capture: one row per point of every
// scan the driver assembles, and a summary with the driver's counts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <set>

#include "drivers/rs16/driver.hpp"
#include "drivers/rs16/pcap_source.hpp"
#include "test/drivers/rs16/vendor_decode.hpp"
#include "test/fixtures.hpp"
#include "test/tools/dump/dump_runner.hpp"

namespace tumble::test {
namespace {

constexpr const char* kPcap = "rs16/rs16_synthetic.pcap";
constexpr const char* kVendor = "rs16/rs16_synthetic.vendor-decode.txt";

// Points per scan index as the driver itself assembles them (default options).
std::map<std::uint64_t, std::size_t> driver_points_per_scan() {
  std::map<std::uint64_t, std::size_t> points;
  rs16::Driver driver({}, [&](Scan& scan, const rs16::ScanReport&) { points[scan.index] = scan.points.size(); });
  rs16::PcapSource source(fixture_path(kPcap).string(), {});
  while (const auto d = source.next()) driver.on_datagram(*d);
  return points;
}

TEST(DumpRs16, OneRowPerPointOfEveryAssembledScan) {
  TUMBLE_REQUIRE_FIXTURE(kPcap);
  TUMBLE_REQUIRE_FIXTURE(kVendor);
  const DumpRun run = run_dump({"rs16", fixture_path(kPcap).string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  const std::vector<std::string> lines = lines_of(run.out);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.front(), "scan,laser,t_s,x,y,z,intensity,azimuth_deg");

  std::map<std::uint64_t, std::size_t> rows_per_scan;
  std::set<int> lasers;
  double first_t_s = 0, last_t_s = 0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string> f = fields_of(lines[i]);
    ASSERT_EQ(f.size(), 8u) << lines[i];
    ++rows_per_scan[std::stoull(f[0])];
    const int laser = std::stoi(f[1]);
    ASSERT_TRUE(laser >= 0 && laser < 16) << lines[i];
    lasers.insert(laser);
    const double t_s = std::stod(f[2]);
    if (i == 1) first_t_s = t_s;
    ASSERT_GE(t_s, last_t_s - 1e-3) << "time runs back at row " << i;  // firing order within 1 ms
    last_t_s = t_s;
    const double range_m = std::hypot(std::stod(f[3]), std::stod(f[4]), std::stod(f[5]));
    ASSERT_TRUE(range_m >= 0.4 && range_m <= 200.0) << lines[i];
    const double intensity = std::stod(f[6]);
    ASSERT_TRUE(intensity >= 0 && intensity <= 255) << lines[i];
    const double azimuth_deg = std::stod(f[7]);
    ASSERT_TRUE(azimuth_deg >= 0 && azimuth_deg < 360) << lines[i];
  }
  EXPECT_EQ(lasers.size(), 16u);
  // The capture starts 2024-01-01 00:00:00 UTC and lasts half a second.
  EXPECT_NEAR(first_t_s, 1704067200.0, 1.0);
  EXPECT_LT(last_t_s - first_t_s, 0.5);

  const auto vendor = rs16::test::read_vendor_decode(fixture_path(kVendor).string());
  EXPECT_EQ(rows_per_scan.size(), static_cast<std::size_t>(vendor.frames));
  EXPECT_EQ(rows_per_scan, driver_points_per_scan());
}

TEST(DumpRs16, SummaryCountsPacketsScansAndDrops) {
  TUMBLE_REQUIRE_FIXTURE(kPcap);
  TUMBLE_REQUIRE_FIXTURE(kVendor);
  const auto vendor = rs16::test::read_vendor_decode(fixture_path(kVendor).string());
  const DumpRun run = run_dump({"rs16", "--summary", fixture_path(kPcap).string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string& out = run.out;
  EXPECT_EQ(out.find("scan,laser"), std::string::npos);
  EXPECT_NE(out.find("msop packets: " + std::to_string(vendor.msop_packets) + " (decoded " +
                     std::to_string(vendor.msop_packets) + ")"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("scans: " + std::to_string(vendor.frames) + "\n"), std::string::npos) << out;
  EXPECT_NE(out.find("bad msop packets: 0 "), std::string::npos) << out;
  EXPECT_NE(out.find("missing packets: 0 "), std::string::npos) << out;
  EXPECT_NE(out.find("time gaps: 0\n"), std::string::npos) << out;
  EXPECT_NE(out.find("duplicate packets (dropped): 0\n"), std::string::npos) << out;
  EXPECT_NE(out.find("late packets: 0 put into their scan, 0 dropped"), std::string::npos) << out;
  EXPECT_NE(out.find("scan rate: 10.00 Hz"), std::string::npos) << out;  // 600 rpm
  std::size_t in_scans = 0;
  for (const auto& [index, points] : driver_points_per_scan()) in_scans += points;
  EXPECT_NE(out.find("(in scans " + std::to_string(in_scans) + ","), std::string::npos) << out;
}

TEST(DumpRs16, TruncatedCapturePrintsWhatCameBeforeThenWarns) {
  TUMBLE_REQUIRE_FIXTURE(kPcap);
  const std::string whole = read_text(fixture_path(kPcap));
  const TempFile cut("truncated.pcap");
  {
    std::ofstream f(cut.path, std::ios::binary);
    f.write(whole.data(), static_cast<std::streamsize>(whole.size() * 3 / 5));  // ends inside a record
  }
  const DumpRun run = run_dump({"rs16", cut.path.string()});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_GT(lines_of(run.out).size(), 1000u);
  EXPECT_NE(run.err.find("truncated"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find(cut.path.string()), std::string::npos) << run.err;
  EXPECT_EQ(lines_of(run.err).size(), 1u) << run.err;
}

}  // namespace
}  // namespace tumble::test
