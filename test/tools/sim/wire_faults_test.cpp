// The byte rewrites of `tumble-sim faults`: a NaN rate of turn in frames
// that still pass the checksum, wherever the serial reads cut them.
#include "tools/sim/wire_faults.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_encode.hpp"
#include "drivers/mti/mti_stream.hpp"
#include "drivers/mti/xbus_frame.hpp"

namespace tumble::sim {
namespace {

std::vector<std::uint8_t> imu_stream(int frames) {
  std::vector<std::uint8_t> stream;
  for (int i = 0; i < frames; ++i) {
    mti::MtData2Out m;
    m.packet_counter = static_cast<std::uint16_t>(i);
    m.sample_time_fine = 100u * static_cast<std::uint32_t>(i);
    m.accel_m_s2 = {0.0, 0.0, 9.81};
    m.gyro_rad_s = {0.1, 0.2, 0.3};
    const auto frame = mti::encode_xbus_frame(mti::mid::kMtData2, mti::encode_mtdata2(m));
    stream.insert(stream.end(), frame.begin(), frame.end());
  }
  return stream;
}

TEST(WireFaults, PoisonedFramesStillDecodeWithANaNRateAndTheOthersAreUntouched) {
  std::vector<std::uint8_t> stream = imu_stream(10);
  int frame = 0;
  const std::uint64_t poisoned = poison_rate_of_turn(stream, [&] { return frame++ % 3 == 0; });
  EXPECT_EQ(poisoned, 4u);  // frames 0, 3, 6, 9
  mti::MtiStream decoder;
  std::vector<ImuSample> samples;
  decoder.feed_untimed(stream, samples);
  ASSERT_EQ(samples.size(), 10u);  // every checksum good
  EXPECT_EQ(decoder.stats().frames.bad_frames(), 0u);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_EQ(std::isnan(samples[i].gyro_rad_s.x()), i % 3 == 0) << i;
    EXPECT_NEAR(samples[i].gyro_rad_s.z(), 0.3, 1e-6) << i;
  }
}

}  // namespace
}  // namespace tumble::sim
