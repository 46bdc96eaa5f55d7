#include "drivers/mti/mti_stream.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_encode.hpp"
#include "drivers/mti/xdi.hpp"
#include "test/drivers/mti/mti_test_util.hpp"

// Counts heap allocations in this test binary, to check the steady state.
// (GCC cannot see that this new and this delete are a malloc/free pair.)
namespace {
std::atomic<std::uint64_t> g_allocations{0};
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

namespace tumble::mti {
namespace {

using Bytes = std::vector<std::uint8_t>;
using test_util::append;

constexpr double kHost0_s = 1.7e9;

Bytes imu_frame(std::uint16_t packet_counter, std::uint32_t stf, std::uint32_t status = 0,
                NumberFormat fmt = NumberFormat::Float32) {
  MtData2Out m;
  m.packet_counter = packet_counter;
  m.sample_time_fine = stf;
  m.accel_m_s2 = Eigen::Vector3d(0.1, -0.2, 9.8);
  m.gyro_rad_s = Eigen::Vector3d(0.01, 0.02, -0.03);
  m.status_word = status;
  return encode_xbus_frame(mid::kMtData2, encode_mtdata2(m, fmt));
}

Bytes gnss_frame(std::uint16_t packet_counter, std::uint32_t stf) {
  Bytes p;
  append_u16_packet(p, xdi::kPacketCounter, packet_counter);
  append_u32_packet(p, xdi::kSampleTimeFine, stf);
  append_raw_packet(p, xdi::kGnssPvtData, Bytes(94, 0));
  return encode_xbus_frame(mid::kMtData2, p);
}

TEST(MtiStream, GnssOnlyMessagesAreCountedButGiveNoSamples) {
  MtiStream stream;
  std::vector<ImuSample> out;
  Bytes bytes = imu_frame(1, 1000);
  append(bytes, gnss_frame(2, 900));  // its own, older sample time
  append(bytes, imu_frame(3, 1100));
  stream.feed_untimed(bytes, out);
  EXPECT_EQ(out.size(), 2u);
  EXPECT_EQ(stream.stats().imu_samples, 2u);
  EXPECT_EQ(stream.stats().non_imu_messages, 1u);
  EXPECT_EQ(stream.stats().mtdata2.messages, 3u);
  EXPECT_EQ(stream.stats().packet_counter_gaps, 0u);
  EXPECT_EQ(stream.stats().sample_time_backwards, 0u);
}

TEST(MtiStream, GapsAreFoundAcrossBothWraps) {
  MtiStream stream;  // 100 Hz: 100 ticks a sample
  std::vector<ImuSample> out;
  Bytes bytes;
  std::uint16_t pc = 65530;
  std::uint32_t stf = 863'999'500;
  for (int i = 0; i < 20; ++i) {
    if (i == 8) {  // lose three messages
      pc = static_cast<std::uint16_t>(pc + 3);
      stf += 300;
    }
    append(bytes, imu_frame(pc, stf % 864'000'000u));
    pc = static_cast<std::uint16_t>(pc + 1);
    stf += 100;
  }
  stream.feed_untimed(bytes, out);
  EXPECT_EQ(out.size(), 20u);
  EXPECT_EQ(stream.stats().packet_counter_gaps, 1u);
  EXPECT_EQ(stream.stats().missing_packets, 3u);
  EXPECT_EQ(stream.stats().sample_time_gaps, 1u);
  for (std::size_t i = 1; i < out.size(); ++i) EXPECT_GT(out[i].t_s, out[i - 1].t_s);
  EXPECT_NEAR(out.back().t_s - out.front().t_s, 0.22, 1e-9);
}

TEST(MtiStream, UntimedBytesAreTimedFromSampleTimeFineAndTheEpoch) {
  MtiStreamOptions options;
  options.epoch_s = 1000.0;
  options.imu_time_offset_s = 0.25;
  MtiStream stream(options);
  std::vector<ImuSample> out;
  stream.feed_untimed(imu_frame(1, 123'456), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].t_s, 1000.0 + 12.3456 + 0.25);
}

// The frame's own time on the wire is taken off its arrival before the
// envelope: the same samples give the same host times at both bauds, although
// a 54-byte frame takes 4.7 ms at 115200 and 0.6 ms at 921600.
TEST(MtiStream, TransmissionTimeIsTakenOffTheArrival) {
  std::vector<double> times[2];
  int run = 0;
  for (const std::uint32_t baud : {115200u, 921600u}) {
    MtiStreamOptions options;
    options.baud = baud;
    MtiStream stream(options);
    std::vector<ImuSample> out;
    for (int i = 0; i < 200; ++i) {
      const auto stf = static_cast<std::uint32_t>(50'000 + 100 * i);
      const double sample_host_s = kHost0_s + i * 0.01;
      if (i % 2 == 0 || i + 1 == 200) {  // one frame per read
        const Bytes f = imu_frame(static_cast<std::uint16_t>(i), stf);
        stream.feed(f, sample_host_s + 0.001 + f.size() * 10.0 / baud, out);
      } else {  // this frame and the next in one read, arriving after both
        Bytes two = imu_frame(static_cast<std::uint16_t>(i), stf);
        const Bytes next = imu_frame(static_cast<std::uint16_t>(i + 1), stf + 100);
        append(two, next);
        stream.feed(two, sample_host_s + 0.01 + 0.001 + next.size() * 10.0 / baud, out);
        ++i;
      }
    }
    ASSERT_EQ(out.size(), 200u);
    for (const ImuSample& s : out) times[run].push_back(s.t_s);
    ++run;
  }
  for (std::size_t i = 0; i < times[0].size(); ++i) {
    EXPECT_NEAR(times[0][i], times[1][i], 1e-6) << i;
    EXPECT_NEAR(times[0][i], kHost0_s + 0.001 + static_cast<double>(i) * 0.01, 1e-6) << i;
  }
}

TEST(MtiStream, ConfiguringDiscardsMeasurementsAndTheFirstAfterIsDropped) {
  MtiStream stream;
  std::vector<Bytes> control;
  stream.set_control_handler([&control](const XbusFrame& f) { control.emplace_back(f.payload.begin(), f.payload.end()); });
  stream.set_measuring(false);
  std::vector<ImuSample> out;
  Bytes bytes = imu_frame(1, 100);
  append(bytes, encode_xbus_frame(mid::kGoToMeasurementAck, {}));
  stream.feed(bytes, kHost0_s, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(stream.stats().discarded_while_configuring, 1u);
  EXPECT_EQ(control.size(), 1u);
  stream.set_measuring(true, true);
  Bytes measuring = imu_frame(2, 200);
  append(measuring, imu_frame(3, 300));
  append(measuring, encode_xbus_frame(mid::kError, Bytes{41}));
  stream.feed(measuring, kHost0_s + 1, out);
  EXPECT_EQ(out.size(), 1u);
  EXPECT_EQ(stream.stats().stale_samples_dropped, 1u);
  EXPECT_EQ(stream.stats().device_errors, 1u);
  EXPECT_EQ(stream.stats().other_frames, 2u);
  EXPECT_EQ(control.size(), 2u);
}

TEST(MtiStream, ClipFlagsAreCountedPerAxis) {
  MtiStream stream;
  std::vector<ImuSample> out;
  Bytes bytes = imu_frame(1, 100, (1u << 10) | (1u << 12) | (1u << 19));  // accel Z, gyro Y
  append(bytes, imu_frame(2, 200, 1u << 8));                               // accel X
  append(bytes, imu_frame(3, 300));
  stream.feed_untimed(bytes, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(stream.stats().clipped_samples, 2u);
  EXPECT_EQ(stream.stats().accel_saturated, (std::array<std::uint64_t, 3>{1, 0, 1}));
  EXPECT_EQ(stream.stats().gyro_saturated, (std::array<std::uint64_t, 3>{0, 1, 0}));
  EXPECT_TRUE(out[0].gyro_saturated[1] && out[0].accel_saturated[2]);
}

TEST(MtiStream, ADeviceRestartStartsTheTimeMappingAfresh) {
  MtiStream stream;
  std::vector<ImuSample> out;
  for (int i = 0; i < 50; ++i)
    stream.feed(imu_frame(static_cast<std::uint16_t>(i), static_cast<std::uint32_t>(5'000'000 + 100 * i)),
                kHost0_s + i * 0.01, out);
  // Power cycled: the sample clock starts again near zero, 2 s later.
  for (int i = 0; i < 50; ++i)
    stream.feed(imu_frame(static_cast<std::uint16_t>(i), static_cast<std::uint32_t>(100 * i)),
                kHost0_s + 2.5 + i * 0.01, out);
  ASSERT_EQ(out.size(), 100u);
  EXPECT_EQ(stream.stats().sensor_clock_restarts, 1u);
  EXPECT_NEAR(out[50].t_s, kHost0_s + 2.5, 0.01);
  EXPECT_NEAR(out[99].t_s, kHost0_s + 2.99, 0.01);
}

TEST(MtiStream, ASampleClockRunningAheadOfTheHostIsARestart) {
  MtiStream stream;
  std::vector<ImuSample> out;
  stream.feed(imu_frame(1, 100), kHost0_s, out);
  stream.feed(imu_frame(2, 200), kHost0_s + 0.01, out);
  stream.feed(imu_frame(3, 800'000'000), kHost0_s + 0.02, out);  // 80'000 s ahead
  stream.feed(imu_frame(4, 800'000'100), kHost0_s + 0.03, out);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(stream.stats().sensor_clock_restarts, 1u);
  const double on_wire_s = 54 * 10.0 / 115200;
  EXPECT_NEAR(out[3].t_s, kHost0_s + 0.03 - on_wire_s, 1e-6);
}

TEST(MtiStream, ARepeatedSampleTimeIsDropped) {
  MtiStream stream;
  std::vector<ImuSample> out;
  Bytes bytes = imu_frame(1, 100);
  append(bytes, imu_frame(2, 100));
  append(bytes, imu_frame(3, 200));
  stream.feed_untimed(bytes, out);
  EXPECT_EQ(out.size(), 2u);
  EXPECT_EQ(stream.stats().sample_time_backwards, 1u);
}

TEST(MtiStream, DuplicatedAndLateFramesAreDroppedAndCountedNeverFedBackInTime) {
  MtiStream stream;
  std::vector<ImuSample> out;
  const double period_s = 0.01;
  // Counters 1 2 2 4 3 5 6 4: a duplicate, one frame overtaken, one far too late.
  const std::uint16_t counters[] = {1, 2, 2, 4, 3, 5, 6, 4};
  for (std::size_t i = 0; i < std::size(counters); ++i) {
    const std::uint16_t c = counters[i];
    stream.feed(imu_frame(c, 100u * c), kHost0_s + period_s * static_cast<double>(i), out);
  }
  ASSERT_EQ(out.size(), 5u);  // 1 2 4 5 6
  for (std::size_t i = 1; i < out.size(); ++i) EXPECT_LT(out[i - 1].t_s, out[i].t_s);
  EXPECT_EQ(stream.stats().duplicate_frames, 1u);
  EXPECT_EQ(stream.stats().out_of_order_frames, 2u);
  EXPECT_EQ(stream.stats().packet_counter_gaps, 1u);  // 3 had not come when 4 did
  EXPECT_EQ(stream.stats().missing_packets, 1u);
  EXPECT_EQ(stream.stats().sample_time_backwards, 0u);
  EXPECT_EQ(stream.stats().sensor_clock_restarts, 0u);
}

TEST(MtiStream, SamplesWithoutSampleTimeUseTheArrivalOrAreDropped) {
  Bytes p;
  append_reals_packet(p, xdi::kAcceleration, std::array<double, 3>{0, 0, 9.8}, NumberFormat::Float32);
  append_reals_packet(p, xdi::kRateOfTurn, std::array<double, 3>{0, 0, 0}, NumberFormat::Float32);
  const Bytes frame = encode_xbus_frame(mid::kMtData2, p);
  MtiStream timed;
  std::vector<ImuSample> out;
  timed.feed(frame, kHost0_s + 1.0, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].t_s, kHost0_s + 1.0 - frame.size() * 10.0 / 115200, 1e-6);
  EXPECT_EQ(timed.stats().samples_without_sample_time, 1u);
  MtiStream untimed;
  out.clear();
  untimed.feed_untimed(frame, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(untimed.stats().samples_without_sample_time, 1u);
}

TEST(MtiStream, FinishDecodesFramesHiddenBehindACutOne) {
  Bytes bytes{kPreamble, kBusIdMaster, mid::kMtData2, kExtendedLength, 0x04, 0x00};
  append(bytes, imu_frame(1, 100));
  MtiStream stream;
  std::vector<ImuSample> out;
  stream.feed_untimed(bytes, out);
  EXPECT_TRUE(out.empty());
  stream.finish(out);
  EXPECT_EQ(out.size(), 1u);
  EXPECT_EQ(stream.stats().frames.cut_off, 1u);
}

TEST(MtiStream, SteadyStateFeedDoesNotAllocate) {
  Bytes bytes;
  for (int i = 0; i < 1200; ++i)
    append(bytes, imu_frame(static_cast<std::uint16_t>(i), static_cast<std::uint32_t>(1000 + 100 * i)));
  MtiStream stream;
  std::vector<ImuSample> out;
  const std::size_t warm_up = 200 * 54;
  stream.feed(std::span(bytes).first(warm_up), kHost0_s, out);
  out.clear();
  const std::uint64_t before = g_allocations.load();
  for (std::size_t pos = warm_up; pos < bytes.size(); pos += 64) {
    const std::size_t n = std::min<std::size_t>(64, bytes.size() - pos);
    stream.feed(std::span(bytes).subspan(pos, n), kHost0_s + static_cast<double>(pos) * 1e-5, out);
    if (out.size() > 150) out.clear();
  }
  EXPECT_EQ(g_allocations.load() - before, 0u);
  EXPECT_EQ(stream.stats().imu_samples, 1200u);
}

}  // namespace
}  // namespace tumble::mti
