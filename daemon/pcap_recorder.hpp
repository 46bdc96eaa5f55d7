// record.dir: the live sensors' data as it arrived, in segments that each
// replay on their own (`tumbled --replay DIR/<date-time>/lidar.pcap
// DIR/<date-time>/imu.pcap`; tumble-dump reads them): a new directory named
// by its start time for each start of tumbled and each rotation, so nothing
// is ever overwritten.
//
// The odometry never waits for it. The io thread only copies each accepted
// lidar datagram (with its real sender) and each serial read into a bounded
// ring (kQueueItems, about 4 s of both sensors) and counts what finds it full.
// A writer thread at normal priority writes the segments, checks every write,
// syncs every daemon.checkpoint_period_s and at each rotation (after
// record.max_segment_mib or record.max_segment_s), and pauses below
// record.min_free_mib of free space or after a write error, retrying in a new
// segment every kRetryPeriod_s. Failures are logged and counted in status_t
// (record_dropped, record_errors, record_paused); none stops tumbled.
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "daemon/config.hpp"
#include "daemon/rate_limited_log.hpp"
#include "daemon/seams.hpp"
#include "daemon/spsc_ring.hpp"
#include "drivers/mti/imu_recording_writer.hpp"
#include "drivers/rs16/lidar_datagram.hpp"
#include "drivers/rs16/recording_writer.hpp"

namespace tumble::daemon {

class PcapRecorder : public Recorder {
 public:
  static constexpr std::size_t kQueueItems = 4096;  // 750 MSOP + 100-400 serial reads a second
  static constexpr std::size_t kItemBytes = 2048;   // a longer serial read takes several items
  static constexpr double kRetryPeriod_s = 10.0;

  // Starts the writer thread; never throws for the disk's sake (the first
  // segment is created there, and a failure is reported like any other).
  PcapRecorder(const RecordConfig& config, const rs16::SourceConfig& ports, double checkpoint_period_s);
  ~PcapRecorder() override;
  PcapRecorder(const PcapRecorder&) = delete;
  PcapRecorder& operator=(const PcapRecorder&) = delete;

  void record_lidar(const LidarDatagram& datagram) override;
  void record_imu(const ImuBytes& bytes) override;
  void report(PipelineCounters& counters) const override;
  // Writes what is queued, syncs and closes the segment; stops the writer.
  void flush() override;

  // The segments' directories so far (writer thread; read after flush()).
  const std::vector<std::string>& segments() const { return segments_; }

 private:
  enum class Kind : std::uint8_t { Msop, Difop, Imu };
  struct Item {
    Kind kind = Kind::Imu;
    std::uint16_t size = 0;
    std::uint32_t source_ip = 0;
    double arrival_s = 0.0;  // host clock, as the sources stamp it
    std::array<std::uint8_t, kItemBytes> bytes{};
  };
  struct Segment {
    std::string directory;
    std::unique_ptr<rs16::RecordingWriter> lidar;
    std::unique_ptr<mti::ImuRecordingWriter> imu;
    double opened_s = 0.0;
  };

  void enqueue(Kind kind, double arrival_s, std::uint32_t source_ip, std::span<const std::uint8_t> bytes);
  // Writer thread:
  void write_until_stopped();
  void write(const Item& item, double now_s);
  bool open_segment(double now_s);
  void close_segment(double now_s);  // syncs first
  void sync(double now_s);
  void fail(const std::string& what, double now_s);
  bool room_on_disk(double now_s);
  void dropped(std::int64_t items);
  void report_queue_drops(double now_s);

  RecordConfig config_;
  rs16::SourceConfig ports_;
  double checkpoint_period_s_;
  // Written by both threads, copied into status_t by report().
  std::atomic<std::int64_t> dropped_{0};
  std::atomic<std::int64_t> errors_{0};
  std::atomic<bool> paused_{false};
  SpscRing<Item> queue_;
  std::atomic<std::int64_t> queue_drops_{0};  // io thread: items that found the ring full
  std::int64_t queue_drops_reported_ = 0;
  std::optional<Segment> segment_;
  std::vector<std::string> segments_;
  double next_sync_s_ = 0.0;
  double paused_until_s_ = 0.0;  // after a failure: no segment before then
  double next_space_check_s_ = 0.0;
  RateLimitedLog log_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread writer_;  // last: starts once everything above exists
};

}  // namespace tumble::daemon
