#include "daemon/pcap_recorder.hpp"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <sys/statvfs.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "daemon/steady_time.hpp"
#include "daemon/thread_setup.hpp"

namespace tumble::daemon {

namespace {

constexpr std::chrono::milliseconds kWriterPeriod{50};  // the ring holds 80 times this at full rate
constexpr double kSpaceCheckPeriod_s = 1.0;
constexpr std::int64_t kMiB = 1 << 20;

double steady_s() { return static_cast<double>(steady_now_ns()) * 1e-9; }

// The integer nanoseconds a replay turns back into exactly t_s, so that a
// recording replays with the very times the live run used. The lidar's pcap
// is read as seconds plus nanoseconds (rs16::PcapSource, as the live socket
// stamps); serial reads as double(ns) * 1e-9 (as the live serial reader
// stamps), which is constant over runs of up to 256 ns near today's times:
// the nearest nanosecond that maps back is searched for.
std::int64_t lidar_ns(double t_s) {
  const double whole_s = std::floor(t_s);
  return static_cast<std::int64_t>(whole_s) * 1'000'000'000 + std::llround((t_s - whole_s) * 1e9);
}

std::int64_t imu_ns(double t_s) {
  const std::int64_t nearest = std::llround(t_s * 1e9);
  for (std::int64_t offset = 0; offset <= 1024; ++offset) {
    if (static_cast<double>(nearest + offset) * 1e-9 == t_s) return nearest + offset;
    if (static_cast<double>(nearest - offset) * 1e-9 == t_s) return nearest - offset;
  }
  return nearest;
}

// DIR/YYYYmmdd-HHMMSS, or with -N when a segment of that second exists.
std::filesystem::path new_segment_path(const std::string& dir) {
  const auto now = std::chrono::floor<std::chrono::seconds>(std::chrono::system_clock::now());
  std::filesystem::path path = std::filesystem::path(dir) / fmt::format("{:%Y%m%d-%H%M%S}", now);
  for (int suffix = 1; std::filesystem::exists(path); ++suffix)
    path = std::filesystem::path(dir) / fmt::format("{:%Y%m%d-%H%M%S}-{}", now, suffix);
  return path;
}

}  // namespace

PcapRecorder::PcapRecorder(const RecordConfig& config, const rs16::SourceConfig& ports, double checkpoint_period_s)
    : config_(config),
      ports_(ports),
      checkpoint_period_s_(checkpoint_period_s),
      queue_(kQueueItems),
      log_(1, 10.0),
      writer_([this] { write_until_stopped(); }) {}

PcapRecorder::~PcapRecorder() { flush(); }

void PcapRecorder::record_lidar(const LidarDatagram& datagram) {
  const Kind kind = datagram.dst_port == ports_.difop_port ? Kind::Difop : Kind::Msop;
  enqueue(kind, datagram.arrival_s, datagram.src_ip, datagram.payload);
}

void PcapRecorder::record_imu(const ImuBytes& bytes) { enqueue(Kind::Imu, bytes.arrival_s, 0, bytes.bytes); }

void PcapRecorder::enqueue(Kind kind, double arrival_s, std::uint32_t source_ip, std::span<const std::uint8_t> bytes) {
  // A lidar datagram is one record (1248 bytes); serial bytes are a stream, so
  // a long read may be cut into several records of the same arrival time.
  do {
    const std::size_t n = std::min(bytes.size(), kItemBytes);
    if (queue_.full()) {
      queue_drops_.fetch_add(1, std::memory_order_relaxed);
      dropped_.fetch_add(1, std::memory_order_relaxed);
    } else {
      queue_.push_with([&](Item& item) {
        item.kind = kind;
        item.size = static_cast<std::uint16_t>(n);
        item.source_ip = source_ip;
        item.arrival_s = arrival_s;
        std::memcpy(item.bytes.data(), bytes.data(), n);
      });
    }
    bytes = bytes.subspan(n);
  } while (kind == Kind::Imu && !bytes.empty());
}

void PcapRecorder::report(PipelineCounters& counters) const {
  constexpr auto relaxed = std::memory_order_relaxed;
  counters.record_dropped.store(dropped_.load(relaxed), relaxed);
  counters.record_errors.store(errors_.load(relaxed), relaxed);
  counters.record_paused.store(paused_.load(relaxed), relaxed);
}

void PcapRecorder::flush() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  if (writer_.joinable()) writer_.join();
}

void PcapRecorder::write_until_stopped() {
  name_this_thread("tumble-rec");
  std::unique_lock lock(mutex_);
  for (;;) {
    const bool stopping = wake_.wait_for(lock, kWriterPeriod, [this] { return stopping_; });
    lock.unlock();
    const double now_s = steady_s();
    while (queue_.pop_with([&](const Item& item) { write(item, now_s); })) {
    }
    report_queue_drops(now_s);
    if (segment_ && !stopping) {
      const bool rotate = now_s - segment_->opened_s >= config_.max_segment_s ||
                          segment_->lidar->file().bytes() + segment_->imu->file().bytes() >=
                              static_cast<std::int64_t>(config_.max_segment_mib) * kMiB;
      if (rotate) {
        close_segment(now_s);  // the next item opens the next one
      } else if (now_s >= next_space_check_s_ && !room_on_disk(now_s)) {
        close_segment(now_s);
      } else if (now_s >= next_sync_s_) {
        sync(now_s);
      }
    }
    if (stopping) {
      if (segment_) close_segment(now_s);
      return;
    }
    lock.lock();
  }
}

void PcapRecorder::write(const Item& item, double now_s) {
  if (!segment_ && !open_segment(now_s)) {
    dropped(1);
    return;
  }
  const std::span<const std::uint8_t> bytes(item.bytes.data(), item.size);
  if (item.kind == Kind::Imu) {
    segment_->imu->write(imu_ns(item.arrival_s), bytes);
  } else {
    const rs16::PacketKind kind = item.kind == Kind::Msop ? rs16::PacketKind::Msop : rs16::PacketKind::Difop;
    segment_->lidar->write_from(item.source_ip, lidar_ns(item.arrival_s), kind, bytes);
  }
  if (segment_->lidar->file().failed() || segment_->imu->file().failed()) {
    dropped(1);  // at least: what stdio held when the write failed is gone too
    fail(fmt::format("writing into {} failed: {}", segment_->directory, std::strerror(errno)), now_s);
  }
}

bool PcapRecorder::open_segment(double now_s) {
  if (now_s < paused_until_s_) return false;
  std::error_code error;
  std::filesystem::create_directories(config_.dir, error);
  if (error) {
    fail(fmt::format("cannot create record.dir {}: {}", config_.dir, error.message()), now_s);
    return false;
  }
  if (!room_on_disk(now_s)) return false;
  const std::filesystem::path path = new_segment_path(config_.dir);
  std::filesystem::create_directory(path, error);
  if (error) {
    fail(fmt::format("cannot create {}: {}", path.string(), error.message()), now_s);
    return false;
  }
  rs16::RecordingAddresses addresses;
  addresses.msop_port = ports_.msop_port;
  addresses.difop_port = ports_.difop_port;
  try {
    Segment segment;
    segment.directory = path.string();
    segment.lidar = std::make_unique<rs16::RecordingWriter>((path / "lidar.pcap").string(), addresses);
    segment.imu = std::make_unique<mti::ImuRecordingWriter>((path / "imu.pcap").string());
    segment.opened_s = now_s;
    segment_ = std::move(segment);
  } catch (const pcap::Error& e) {
    fail(e.what(), now_s);
    return false;
  }
  segments_.push_back(path.string());
  next_sync_s_ = now_s + checkpoint_period_s_;
  paused_.store(false, std::memory_order_relaxed);
  spdlog::info("recording the sensors into {}", path.string());
  return true;
}

void PcapRecorder::sync(double now_s) {
  const int lidar_error = segment_->lidar->file().sync();
  const int error = lidar_error != 0 ? lidar_error : segment_->imu->file().sync();
  next_sync_s_ = now_s + checkpoint_period_s_;
  if (error != 0) fail(fmt::format("syncing {} failed: {}", segment_->directory, std::strerror(error)), now_s);
}

void PcapRecorder::close_segment(double now_s) {
  sync(now_s);
  if (!segment_) return;  // the sync failed and said so
  segment_->lidar->close();
  segment_->imu->close();
  segment_.reset();
}

void PcapRecorder::fail(const std::string& what, double now_s) {
  errors_.fetch_add(1, std::memory_order_relaxed);
  paused_.store(true, std::memory_order_relaxed);
  log_.warn("failure", now_s, "record: {}; recording paused, trying again in a new segment in {:.0f} s ({} failures)",
            what, kRetryPeriod_s, errors_.load(std::memory_order_relaxed));
  segment_.reset();
  paused_until_s_ = now_s + kRetryPeriod_s;
}

bool PcapRecorder::room_on_disk(double now_s) {
  next_space_check_s_ = now_s + kSpaceCheckPeriod_s;
  struct statvfs disk {};
  if (::statvfs(config_.dir.c_str(), &disk) != 0) return true;  // the write will say what is wrong
  const auto free_bytes = static_cast<std::int64_t>(disk.f_bavail) * static_cast<std::int64_t>(disk.f_frsize);
  if (free_bytes >= static_cast<std::int64_t>(config_.min_free_mib) * kMiB) return true;
  paused_.store(true, std::memory_order_relaxed);
  log_.warn("space", now_s,
            "record: {} MiB free on {}, below record.min_free_mib ({} MiB): recording paused, checked again every "
            "{:.0f} s",
            free_bytes / kMiB, config_.dir, config_.min_free_mib, kRetryPeriod_s);
  paused_until_s_ = now_s + kRetryPeriod_s;
  return false;
}

void PcapRecorder::dropped(std::int64_t items) {
  dropped_.fetch_add(items, std::memory_order_relaxed);
}

void PcapRecorder::report_queue_drops(double now_s) {
  const std::int64_t drops = queue_drops_.load(std::memory_order_relaxed);
  if (drops == queue_drops_reported_) return;
  log_.warn("queue", now_s, "record: the writer fell {} items behind: {} not recorded so far", kQueueItems, drops);
  queue_drops_reported_ = drops;
}

}  // namespace tumble::daemon
