// tumble-dump mti on real MTi frames: one row per IMU sample with sensor time,
// status word and the clipped axes, and a summary with the driver's counts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "drivers/mti/imu_recording_reader.hpp"
#include "test/fixtures.hpp"
#include "test/tools/dump/dump_runner.hpp"

namespace tumble::test {
namespace {

constexpr const char* kEinride = "mti/einride-mti-g-710/1/output.bin";
constexpr const char* kClipping = "mti/mti-300-frames/test_parse_mdata2_shake_clipping.bin";
constexpr const char* kHeader = "t_sensor_s,t_host_s,ax,ay,az,gx,gy,gz,status_word,saturated_axes";

std::size_t driver_sample_count(const std::string& path) {
  mti::ImuRecordingReader reader(path, {});
  std::vector<ImuSample> samples;
  while (reader.next(samples)) {
  }
  return samples.size();
}

TEST(DumpMti, OneRowPerImuSampleWithSensorTimeAndStatus) {
  TUMBLE_REQUIRE_FIXTURE(kEinride);
  const std::string path = fixture_path(kEinride).string();
  const DumpRun run = run_dump({"mti", path});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::vector<std::string> lines = lines_of(run.out);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.front(), kHeader);
  const std::size_t samples = driver_sample_count(path);
  EXPECT_GT(samples, 50u);
  EXPECT_EQ(lines.size() - 1, samples);

  double previous_sensor_s = 0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string> f = fields_of(lines[i]);
    ASSERT_EQ(f.size(), 10u) << lines[i];
    const double sensor_s = std::stod(f[0]);
    // 100 Hz IMU output; without arrival times host time = sensor time.
    if (i > 1) {
      EXPECT_NEAR(sensor_s - previous_sensor_s, 0.01, 1e-9) << lines[i];
    }
    previous_sensor_s = sensor_s;
    EXPECT_NEAR(std::stod(f[1]), sensor_s, 1e-6);
    const double g_m_s2 = std::hypot(std::stod(f[2]), std::stod(f[3]), std::stod(f[4]));
    EXPECT_TRUE(g_m_s2 > 5.0 && g_m_s2 < 15.0) << lines[i];  // a vehicle, not a tumbling cage
    ASSERT_EQ(f[8].size(), 10u) << lines[i];
    EXPECT_EQ(f[8].substr(0, 2), "0x");
    EXPECT_TRUE(f[9].empty()) << lines[i];
  }
}

TEST(DumpMti, ClippingFrameNamesTheClippedAxes) {
  TUMBLE_REQUIRE_FIXTURE(kClipping);
  const DumpRun run = run_dump({"mti", fixture_path(kClipping).string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::vector<std::string> lines = lines_of(run.out);
  ASSERT_EQ(lines.size(), 2u) << run.out;
  const std::vector<std::string> f = fields_of(lines[1]);
  ASSERT_EQ(f.size(), 10u) << lines[1];
  // Status bits 10 (accel Z), 12 (gyro Y) and 19 (any clipping).
  EXPECT_EQ(f[8], "0x00481401");
  EXPECT_EQ(f[9], "aZ gY");
}

TEST(DumpMti, SummaryCountsFramesSamplesAndSaturation) {
  TUMBLE_REQUIRE_FIXTURE(kEinride);
  TUMBLE_REQUIRE_FIXTURE(kClipping);
  const std::string path = fixture_path(kEinride).string();
  const DumpRun run = run_dump({"mti", "--summary", path});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string& out = run.out;
  const std::size_t samples = driver_sample_count(path);
  EXPECT_NE(out.find("frames: 100\n"), std::string::npos) << out;  // the fixture holds 100 frames
  EXPECT_NE(out.find("imu samples: " + std::to_string(samples) + "\n"), std::string::npos) << out;
  EXPECT_NE(out.find("non-imu messages: " + std::to_string(100 - samples) + "\n"), std::string::npos) << out;
  EXPECT_NE(out.find("sample rate: 100.00 Hz"), std::string::npos) << out;
  EXPECT_NE(out.find("sample time gaps: 0\n"), std::string::npos) << out;
  EXPECT_NE(out.find("duplicate frames (dropped): 0\n"), std::string::npos) << out;
  EXPECT_NE(out.find("out-of-order frames (dropped): 0\n"), std::string::npos) << out;
  EXPECT_NE(out.find("clipped samples: 0\n"), std::string::npos) << out;
  EXPECT_NE(out.find("problem: none"), std::string::npos) << out;

  const DumpRun clipping = run_dump({"mti", "--summary", fixture_path(kClipping).string()});
  ASSERT_EQ(clipping.exit_code, 0) << clipping.err;
  EXPECT_NE(clipping.out.find("clipped samples: 1\n"), std::string::npos) << clipping.out;
  EXPECT_NE(clipping.out.find("saturated: aX 0 aY 0 aZ 1 gX 0 gY 1 gZ 0"), std::string::npos) << clipping.out;
}

TEST(DumpMti, TruncatedStreamPrintsWhatCameBeforeThenWarns) {
  TUMBLE_REQUIRE_FIXTURE(kEinride);
  const std::string whole = read_text(fixture_path(kEinride));
  const TempFile cut("truncated.bin");
  {
    std::ofstream f(cut.path, std::ios::binary);
    f.write(whole.data(), static_cast<std::streamsize>(whole.size() / 2));
  }
  const DumpRun run = run_dump({"mti", cut.path.string()});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(lines_of(run.out).size() - 1, driver_sample_count(cut.path.string()));
  EXPECT_NE(run.err.find("truncated"), std::string::npos) << run.err;
  EXPECT_EQ(lines_of(run.err).size(), 1u) << run.err;
}

}  // namespace
}  // namespace tumble::test
