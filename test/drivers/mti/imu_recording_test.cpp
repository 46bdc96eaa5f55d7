#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "drivers/mti/imu_recording_reader.hpp"
#include "drivers/mti/imu_recording_writer.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_encode.hpp"
#include "test/drivers/mti/mti_test_util.hpp"
#include "test/fixtures.hpp"

namespace tumble::mti {
namespace {

using Bytes = std::vector<std::uint8_t>;

// A file under the temp directory, removed when the test ends.
class TempFile {
 public:
  explicit TempFile(const std::string& name)
      : path_((std::filesystem::temp_directory_path() /
               ("tumble_mti_" + std::to_string(::getpid()) + "_" + name))
                  .string()) {}
  ~TempFile() { std::filesystem::remove(path_); }
  const std::string& path() const { return path_; }
  void write(const Bytes& bytes) const {
    std::ofstream(path_, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                 static_cast<std::streamsize>(bytes.size()));
  }

 private:
  std::string path_;
};

Bytes frames(int first, int n) {
  Bytes bytes;
  for (int i = first; i < first + n; ++i) {
    MtData2Out m;
    m.packet_counter = static_cast<std::uint16_t>(i);
    m.sample_time_fine = static_cast<std::uint32_t>(100 * i);
    m.accel_m_s2 = Eigen::Vector3d(0, 0, 9.81);
    test_util::append(bytes, encode_xbus_frame(mid::kMtData2, encode_mtdata2(m)));
  }
  return bytes;
}

std::vector<ImuSample> read_all(ImuRecordingReader& reader) {
  std::vector<ImuSample> samples;
  while (reader.next(samples)) {
  }
  return samples;
}

TEST(ImuRecording, PcapRecordsReplayWithTheirArrivalTimes) {
  TempFile file("replay.pcap");
  const std::int64_t t0_ns = 1'700'000'000'000'000'000;
  {
    ImuRecordingWriter writer(file.path());
    for (int read = 0; read < 50; ++read) {
      const Bytes two = frames(2 * read, 2);  // two 54-byte frames per serial read, 20 ms apart
      writer.write(t0_ns + read * 20'000'000 + 20'000'000, two);
    }
  }
  ImuRecordingReader reader(file.path(), MtiStreamOptions{});
  EXPECT_EQ(reader.format(), RecordingFormat::Pcap);
  const auto samples = read_all(reader);
  ASSERT_EQ(samples.size(), 100u);
  EXPECT_EQ(reader.reads(), 50u);
  EXPECT_EQ(reader.problem(), "");
  // The second frame of each read ended as the read returned: its time is
  // the arrival less its own 4.7 ms on the wire.
  EXPECT_NEAR(samples[1].t_s, 1.7e9 + 0.02 - 54 * 10.0 / 115200, 1e-6);
  // Once the envelope has seen a second frame (the lower one of each read):
  for (std::size_t i = 2; i < samples.size(); ++i) EXPECT_NEAR(samples[i].t_s - samples[i - 1].t_s, 0.01, 1e-6);
}

TEST(ImuRecording, RawByteStreamsAreTimedFromSampleTimeFine) {
  TempFile file("raw.mtb");
  Bytes bytes{0x12, 0x34, 0xFA};  // recordings start mid-frame
  test_util::append(bytes, frames(0, 200));  // > 4096 bytes: frames cross chunk boundaries
  file.write(bytes);
  MtiStreamOptions options;
  options.epoch_s = 1000.0;
  ImuRecordingReader reader(file.path(), options);
  EXPECT_EQ(reader.format(), RecordingFormat::RawBytes);
  const auto samples = read_all(reader);
  ASSERT_EQ(samples.size(), 200u);
  EXPECT_DOUBLE_EQ(samples[5].t_s, 1000.05);
  EXPECT_EQ(reader.stats().frames.bytes_discarded, 3u);
  EXPECT_EQ(reader.problem(), "");
}

TEST(ImuRecording, TheFixtureByteStreamReplays) {
  TUMBLE_REQUIRE_FIXTURE("mti/einride-mti-g-710/1/output.bin");
  ImuRecordingReader reader(test::fixture_path("mti/einride-mti-g-710/1/output.bin").string(), MtiStreamOptions{});
  EXPECT_EQ(read_all(reader).size(), 96u);
  EXPECT_EQ(reader.stats().non_imu_messages, 4u);
  EXPECT_EQ(reader.problem(), "");
}

TEST(ImuRecording, ALidarPcapIsRefusedByItsLinkType) {
  TempFile file("lidar.pcap");
  { pcap::Writer(file.path(), pcap::kLinkEthernet).write(1, Bytes(60, 0)); }
  try {
    ImuRecordingReader reader(file.path(), MtiStreamOptions{});
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              file.path() + ": link type 1 is not LINKTYPE_USER0 (147): not an IMU serial recording");
  }
}

TEST(ImuRecording, AMissingFileIsNamed) {
  try {
    ImuRecordingReader reader("/nonexistent/imu.pcap", MtiStreamOptions{});
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/imu.pcap"), std::string::npos) << e.what();
  }
}

TEST(ImuRecording, ATruncatedPcapKeepsWhatCameBeforeAndSaysSo) {
  TempFile file("cut.pcap");
  {
    ImuRecordingWriter writer(file.path());
    for (int read = 0; read < 10; ++read) writer.write(1'000'000'000LL * (read + 1), frames(read, 1));
  }
  std::filesystem::resize_file(file.path(), std::filesystem::file_size(file.path()) - 20);
  ImuRecordingReader reader(file.path(), MtiStreamOptions{});
  EXPECT_EQ(read_all(reader).size(), 9u);
  EXPECT_NE(reader.problem().find("truncated"), std::string::npos) << reader.problem();
}

TEST(ImuRecording, APcapStoppedInsideAFrameIsWhereTheRecordingStopped) {
  TempFile file("stopped.pcap");
  {
    ImuRecordingWriter writer(file.path());
    for (int read = 0; read < 3; ++read) writer.write(1'000'000'000LL * (read + 1), frames(read, 1));
    Bytes half = frames(3, 1);
    half.resize(half.size() / 2);
    writer.write(4'000'000'000LL, half);
  }
  ImuRecordingReader reader(file.path(), MtiStreamOptions{});
  EXPECT_EQ(read_all(reader).size(), 3u);
  EXPECT_EQ(reader.stats().frames.cut_off, 1u);
  EXPECT_EQ(reader.problem(), "");
}

TEST(ImuRecording, ARawStreamCutInsideAFrameSaysSo) {
  TempFile file("cut.mtb");
  Bytes bytes = frames(0, 3);
  bytes.resize(bytes.size() - 10);
  file.write(bytes);
  ImuRecordingReader reader(file.path(), MtiStreamOptions{});
  EXPECT_EQ(read_all(reader).size(), 2u);
  EXPECT_EQ(reader.stats().frames.cut_off, 1u);
  EXPECT_EQ(reader.stats().frames.bytes_discarded, 44u);
  EXPECT_EQ(reader.problem(), file.path() + ": truncated: the stream ends inside a frame");
}

TEST(ImuRecording, CorruptFramesAreReported) {
  TempFile file("corrupt.mtb");
  Bytes bytes = frames(0, 5);
  bytes[54 + 20] ^= 0xFF;
  file.write(bytes);
  ImuRecordingReader reader(file.path(), MtiStreamOptions{});
  EXPECT_EQ(read_all(reader).size(), 4u);
  EXPECT_EQ(reader.problem(), file.path() + ": 1 corrupt frames skipped (checksum 1, length 0), 54 bytes discarded");
}

TEST(ImuRecording, GarbageIsCountedNotDecoded) {
  TempFile file("garbage.bin");
  Bytes garbage(5000);
  for (std::size_t i = 0; i < garbage.size(); ++i) garbage[i] = static_cast<std::uint8_t>((i * 7919) >> 3);
  file.write(garbage);
  ImuRecordingReader reader(file.path(), MtiStreamOptions{});
  EXPECT_TRUE(read_all(reader).empty());
  EXPECT_EQ(reader.stats().frames.bytes, 5000u);
  EXPECT_EQ(reader.stats().frames.bytes_discarded, 5000u);
  EXPECT_EQ(reader.problem(), file.path() + ": no Xbus frame in 5000 bytes: not an MTi stream");
}

}  // namespace
}  // namespace tumble::mti
