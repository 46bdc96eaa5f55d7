// MTi decoding throughput on one core: frames per second through the frame
// reader alone and through the whole stream (frames -> MTData2 -> timed
// ImuSample), fed in serial-read-sized pieces.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "drivers/mti/frame_reader.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_encode.hpp"
#include "drivers/mti/mti_stream.hpp"

namespace {

using namespace tumble;
using namespace tumble::mti;

constexpr int kFrames = 4000;
constexpr std::size_t kReadBytes = 64;  // a typical serial read at 115200..921600 baud

std::vector<std::uint8_t> imu_stream(NumberFormat fmt) {
  std::vector<std::uint8_t> bytes;
  for (int i = 0; i < kFrames; ++i) {
    MtData2Out m;
    m.packet_counter = static_cast<std::uint16_t>(i);
    m.sample_time_fine = static_cast<std::uint32_t>(25 * i);
    m.accel_m_s2 = Eigen::Vector3d(0.1 * i, -9.81, 0.3);
    m.gyro_rad_s = Eigen::Vector3d(0.01, 2.0, -0.5);
    const auto frame = encode_xbus_frame(mid::kMtData2, encode_mtdata2(m, fmt));
    bytes.insert(bytes.end(), frame.begin(), frame.end());
  }
  return bytes;
}

void BM_FrameReader(benchmark::State& state) {
  const auto bytes = imu_stream(NumberFormat::Float32);
  std::uint64_t frames = 0;
  for (auto _ : state) {
    FrameReader reader;
    for (std::size_t pos = 0; pos < bytes.size(); pos += kReadBytes) {
      reader.push(std::span(bytes).subspan(pos, std::min(kReadBytes, bytes.size() - pos)));
      while (const auto f = reader.next()) benchmark::DoNotOptimize(f->payload.data());
    }
    frames += reader.stats().frames;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(frames));
}
BENCHMARK(BM_FrameReader);

void BM_MtiStream(benchmark::State& state) {
  const auto fmt = static_cast<NumberFormat>(state.range(0));
  const auto bytes = imu_stream(fmt);
  const double seconds_per_byte = 0.0025 * kFrames / static_cast<double>(bytes.size());
  std::vector<ImuSample> samples;
  samples.reserve(kFrames);
  std::uint64_t frames = 0;
  for (auto _ : state) {
    MtiStream stream;
    samples.clear();
    for (std::size_t pos = 0; pos < bytes.size(); pos += kReadBytes) {
      const double arrival_s = 1.7e9 + static_cast<double>(pos) * seconds_per_byte;  // 400 Hz
      stream.feed(std::span(bytes).subspan(pos, std::min(kReadBytes, bytes.size() - pos)), arrival_s, samples);
    }
    benchmark::DoNotOptimize(samples.data());
    frames += stream.stats().frames.frames;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(frames));
  state.SetLabel(std::string(number_format_name(fmt)));
}
BENCHMARK(BM_MtiStream)->DenseRange(0, 3);

// The real MTi-G-710 recording: 100 Hz IMU + 4 Hz GNSS frames, many outputs.
void BM_MtiStreamFixture(benchmark::State& state) {
  const std::filesystem::path path = std::filesystem::path(TUMBLE_FIXTURES_DIR) / "mti/einride-mti-g-710/1/output.bin";
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    state.SkipWithError("fixture mti/einride-mti-g-710/1/output.bin not found");
    return;
  }
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  std::vector<ImuSample> samples;
  std::uint64_t frames = 0;
  for (auto _ : state) {
    MtiStream stream;
    samples.clear();
    stream.feed_untimed(bytes, samples);
    benchmark::DoNotOptimize(samples.data());
    frames += stream.stats().frames.frames;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(frames));
}
BENCHMARK(BM_MtiStreamFixture);

}  // namespace

BENCHMARK_MAIN();
