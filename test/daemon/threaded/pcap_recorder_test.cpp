// The recorder: the lidar's datagrams with their sender, serial reads,
// segments by size and time, the free-space floor, write errors, checkpoints;
// the calls from the io thread never wait for the disk.
#include "daemon/pcap_recorder.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "drivers/pcap/pcap_file.hpp"
#include "drivers/rs16/pcap_source.hpp"
#include "test/temp_dir.hpp"

namespace tumble::daemon {
namespace {

namespace fs = std::filesystem;

constexpr std::uint32_t kSender = 0x0A010203;  // 10.1.2.3
const rs16::SourceConfig kPorts{};

RecordConfig record_into(const fs::path& dir) {
  RecordConfig config;
  config.dir = dir.string();
  config.min_free_mib = 0;
  return config;
}

std::vector<std::uint8_t> payload(std::size_t size, std::uint8_t fill) { return std::vector<std::uint8_t>(size, fill); }

void record_msop(PcapRecorder& recorder, int count, double t0_s = 1700000000.0) {
  const std::vector<std::uint8_t> bytes = payload(1248, 0x55);
  for (int i = 0; i < count; ++i)
    recorder.record_lidar(LidarDatagram{t0_s + i * 0.001332, kSender, kPorts.msop_port, kPorts.msop_port, bytes});
}

std::size_t records_in(const fs::path& file) {
  pcap::Reader reader(file.string());
  std::size_t n = 0;
  while (reader.next()) ++n;
  return n;
}

PipelineCounters& reported(const PcapRecorder& recorder, PipelineCounters& counters) {
  recorder.report(counters);
  return counters;
}

TEST(PcapRecorder, RecordsTheLidarsDatagramsWithTheirSenderAndTheSerialReads) {
  const test::TempDir dir("rec");
  PcapRecorder recorder(record_into(dir.path()), kPorts, 2.0);
  record_msop(recorder, 3);
  const std::vector<std::uint8_t> difop = payload(1248, 0xA5);
  recorder.record_lidar(LidarDatagram{1700000000.5, kSender, kPorts.difop_port, kPorts.difop_port, difop});
  const std::vector<std::uint8_t> serial = payload(5000, 0xFA);  // longer than one queue item
  const double serial_arrival_s = static_cast<double>(1700000000250000123) * 1e-9;  // as the serial reader stamps
  recorder.record_imu(ImuBytes{serial_arrival_s, serial});
  recorder.flush();
  ASSERT_EQ(recorder.segments().size(), 1u);
  const fs::path segment = recorder.segments()[0];
  rs16::PcapSource lidar((segment / "lidar.pcap").string(), kPorts);
  int msop = 0, difop_count = 0;
  while (const auto d = lidar.next()) {
    EXPECT_EQ(d->arrival_s, d->kind == rs16::PacketKind::Difop ? 1700000000.5 : 1700000000.0 + msop * 0.001332);
    EXPECT_EQ(rs16::format_ipv4(d->source_ip), "10.1.2.3");
    ++(d->kind == rs16::PacketKind::Msop ? msop : difop_count);
  }
  EXPECT_EQ(msop, 3);
  EXPECT_EQ(difop_count, 1);
  pcap::Reader imu((segment / "imu.pcap").string());
  std::size_t serial_bytes = 0;
  while (const auto r = imu.next()) {
    EXPECT_EQ(static_cast<double>(r->t_ns) * 1e-9, serial_arrival_s);  // replayed, the very same time
    serial_bytes += r->bytes.size();
  }
  EXPECT_EQ(serial_bytes, serial.size());
  PipelineCounters counters;
  EXPECT_EQ(reported(recorder, counters).record_dropped.load(), 0);
  EXPECT_EQ(counters.record_errors.load(), 0);
  EXPECT_FALSE(counters.record_paused.load());
}

// What a power cut leaves: the checkpoint reached the file while recording.
TEST(PcapRecorder, ACheckpointPutsTheRecordsInTheFileWhileRecording) {
  const test::TempDir dir("rec");
  PcapRecorder recorder(record_into(dir.path()), kPorts, 0.1);
  record_msop(recorder, 10);
  // Read while the recorder still runs, until the checkpoint (0.1 s) shows.
  std::size_t records = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (records < 10 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    for (const auto& entry : fs::directory_iterator(dir.path())) {
      try {
        records = records_in(entry.path() / "lidar.pcap");
      } catch (const pcap::Error&) {  // its header not written yet
      }
    }
  }
  EXPECT_EQ(records, 10u);
  recorder.flush();
}

TEST(PcapRecorder, RotatesBySizeIntoSegmentsThatEachReplay) {
  const test::TempDir dir("rec");
  RecordConfig config = record_into(dir.path());
  config.max_segment_mib = 1;
  PcapRecorder recorder(config, kPorts, 2.0);
  for (int burst = 0; burst < 6; ++burst) {  // 2.3 MiB of frames, in bursts the writer keeps up with
    record_msop(recorder, 300, 1700000000.0 + burst);
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
  }
  recorder.flush();
  ASSERT_GE(recorder.segments().size(), 2u);
  std::size_t total = 0;
  for (const std::string& segment : recorder.segments()) {
    EXPECT_TRUE(fs::exists(fs::path(segment) / "imu.pcap")) << segment;
    total += records_in(fs::path(segment) / "lidar.pcap");
  }
  EXPECT_EQ(total, 1800u);
}

TEST(PcapRecorder, RotatesByTime) {
  const test::TempDir dir("rec");
  RecordConfig config = record_into(dir.path());
  config.max_segment_s = 1.0;
  PcapRecorder recorder(config, kPorts, 2.0);
  for (int i = 0; i < 30; ++i) {  // 3 s or more, whatever the load: at least one rotation
    record_msop(recorder, 1, 1700000000.0 + i * 0.1);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  recorder.flush();
  EXPECT_GE(recorder.segments().size(), 2u);
}

// A floor no disk here meets: nothing is written, everything is counted.
TEST(PcapRecorder, BelowTheFreeSpaceFloorItPausesAndCounts) {
  const test::TempDir dir("rec");
  RecordConfig config = record_into(dir.path());
  config.min_free_mib = 1 << 20;  // 1 TiB
  PcapRecorder recorder(config, kPorts, 2.0);
  record_msop(recorder, 20);
  recorder.flush();
  EXPECT_TRUE(recorder.segments().empty());
  PipelineCounters counters;
  EXPECT_EQ(reported(recorder, counters).record_dropped.load(), 20);
  EXPECT_TRUE(counters.record_paused.load());
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(PcapRecorder, ARecordDirThatCannotBeCreatedIsAnErrorNotAStop) {
  const test::TempDir dir("rec");
  const fs::path file = dir.path() / "a-file";
  std::ofstream(file) << "x";
  PcapRecorder recorder(record_into(file / "records"), kPorts, 2.0);
  record_msop(recorder, 5);
  recorder.flush();
  PipelineCounters counters;
  EXPECT_EQ(reported(recorder, counters).record_errors.load(), 1);  // then paused: no retry within 10 s
  EXPECT_EQ(counters.record_dropped.load(), 5);
  EXPECT_TRUE(counters.record_paused.load());
}

// RLIMIT_FSIZE makes writes past 64 KiB fail (EFBIG), as a full disk would
// mid-segment; the calls keep returning at once and the failure is counted.
TEST(PcapRecorder, AWriteErrorMidSegmentIsCountedAndRecordingPauses) {
  const test::TempDir dir("rec");
  rlimit previous{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &previous), 0);
  const auto old_handler = ::signal(SIGXFSZ, SIG_IGN);
  rlimit small = previous;
  small.rlim_cur = 64 * 1024;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  PipelineCounters counters;
  {
    PcapRecorder recorder(record_into(dir.path()), kPorts, 0.1);
    std::chrono::steady_clock::duration in_calls{};
    for (int burst = 0; burst < 4; ++burst) {
      const auto start = std::chrono::steady_clock::now();
      record_msop(recorder, 100, 1700000000.0 + burst);
      in_calls += std::chrono::steady_clock::now() - start;
      std::this_thread::sleep_for(std::chrono::milliseconds(150));
    }
    EXPECT_LT(in_calls, std::chrono::milliseconds(200));  // 400 copies into the ring, no file I/O
    recorder.flush();
    recorder.report(counters);
  }
  ::setrlimit(RLIMIT_FSIZE, &previous);
  ::signal(SIGXFSZ, old_handler);
  EXPECT_GE(counters.record_errors.load(), 1);
  EXPECT_GE(counters.record_dropped.load(), 1);
  EXPECT_TRUE(counters.record_paused.load());
}

}  // namespace
}  // namespace tumble::daemon
