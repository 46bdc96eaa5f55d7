#include "daemon/replay.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "daemon/driver_params.hpp"

namespace tumble::daemon {

namespace {

constexpr int kRecordsPerTurn = 256;          // then the io_context runs other handlers (stop)
constexpr std::uintmax_t kPcapRecordHeader = 16;
constexpr std::uintmax_t kUdpFrameHeaders = 42;  // Ethernet + IPv4 + UDP, for progress only
constexpr auto kProgressPeriod = std::chrono::seconds(5);

rs16::SourceConfig any_sender(const LidarConfig& lidar) {
  rs16::SourceConfig ports = lidar_source_config(lidar);
  ports.source_ip.reset();  // the decoder filters and counts foreign senders
  return ports;
}

std::string checked_imu_pcap(const std::string& path) {
  pcap::Reader probe(path);
  if (probe.link_type() != pcap::kLinkUser0)
    throw std::runtime_error(fmt::format("{}: link type {} is not an IMU recording (LINKTYPE_USER0 = {})", path,
                                         probe.link_type(), pcap::kLinkUser0));
  return path;
}

std::uintmax_t file_size_or_zero(const std::string& path) {
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  return error ? 0 : size;
}

}  // namespace

class Replay::LidarEnd : public LidarDatagramSource {
 public:
  explicit LidarEnd(std::shared_ptr<Replay> replay) : replay_(std::move(replay)) {}
  void start(std::function<void(const LidarDatagram&)> on_datagram, std::function<void()> on_end) override {
    replay_->on_datagram_ = std::move(on_datagram);
    replay_->on_lidar_end_ = std::move(on_end);
    replay_->started();
  }
  void stop() override { replay_->stop(); }

 private:
  std::shared_ptr<Replay> replay_;
};

class Replay::ImuEnd : public ImuByteSource {
 public:
  explicit ImuEnd(std::shared_ptr<Replay> replay) : replay_(std::move(replay)) {}
  void start(std::function<void(const ImuBytes&)> on_bytes, std::function<void()> on_end) override {
    replay_->on_bytes_ = std::move(on_bytes);
    replay_->on_imu_end_ = std::move(on_end);
    replay_->started();
  }
  void stop() override { replay_->stop(); }

 private:
  std::shared_ptr<Replay> replay_;
};

Replay::Replay(boost::asio::io_context& io, const ReplayFiles& files, const LidarConfig& lidar, ReplayRate rate)
    : io_(io),
      files_(files),
      rate_(rate),
      ports_(any_sender(lidar)),
      lidar_(files.lidar_pcap, ports_),
      imu_(checked_imu_pcap(files.imu_pcap)),
      timer_(io),
      total_bytes_(file_size_or_zero(files.lidar_pcap) + file_size_or_zero(files.imu_pcap)) {}

std::unique_ptr<LidarDatagramSource> Replay::lidar_source() { return std::make_unique<LidarEnd>(shared_from_this()); }
std::unique_ptr<ImuByteSource> Replay::imu_source() { return std::make_unique<ImuEnd>(shared_from_this()); }

void Replay::started() {
  if (++starts_ < 2) return;
  next_lidar_ = lidar_.next();
  next_imu_ = imu_.next();
  const double lidar_s = next_lidar_ ? next_lidar_->arrival_s : INFINITY;
  const double imu_s = next_imu_ ? static_cast<double>(next_imu_->t_ns) * 1e-9 : INFINITY;
  first_record_s_ = std::min(lidar_s, imu_s);
  if (!next_lidar_) spdlog::warn("replay: {} holds no lidar datagrams", files_.lidar_pcap);
  if (!next_imu_) spdlog::warn("replay: {} holds no IMU records", files_.imu_pcap);
  wall_start_ = Clock::now();
  next_progress_ = wall_start_ + kProgressPeriod;
  spdlog::info("replay: {} + {} at {}", files_.lidar_pcap, files_.imu_pcap,
               rate_.max ? std::string("max rate") : fmt::format("{}x real time", rate_.factor));
  boost::asio::post(io_, [self = shared_from_this()] { self->play(); });
}

void Replay::stop() {
  stopped_ = true;
  timer_.cancel();
}

void Replay::advance_lidar() {
  played_bytes_ += next_lidar_->payload.size() + kUdpFrameHeaders + kPcapRecordHeader;
  next_lidar_ = lidar_.next();
}

void Replay::advance_imu() {
  played_bytes_ += next_imu_->bytes.size() + kPcapRecordHeader;
  next_imu_ = imu_.next();
}

void Replay::play() {
  if (stopped_) return;
  for (int n = 0; n < kRecordsPerTurn; ++n) {
    if (!next_lidar_ && !next_imu_) {
      finish();
      return;
    }
    const double imu_s = next_imu_ ? static_cast<double>(next_imu_->t_ns) * 1e-9 : INFINITY;
    const bool lidar_first = next_lidar_ && next_lidar_->arrival_s <= imu_s;
    const double t_s = lidar_first ? next_lidar_->arrival_s : imu_s;
    if (!rate_.max) {
      const auto due = wall_start_ + std::chrono::duration_cast<Clock::duration>(
                                         std::chrono::duration<double>((t_s - first_record_s_) / rate_.factor));
      if (due > Clock::now()) {
        timer_.expires_at(due);
        timer_.async_wait([self = shared_from_this()](const boost::system::error_code& error) {
          if (!error) self->play();
        });
        return;
      }
    }
    last_record_s_ = t_s;
    if (lidar_first) {
      const rs16::LidarDatagram& d = *next_lidar_;
      const std::uint16_t port = d.kind == rs16::PacketKind::Msop ? ports_.msop_port : ports_.difop_port;
      on_datagram_(LidarDatagram{d.arrival_s, d.source_ip, port, port, d.payload});
      advance_lidar();
    } else {
      on_bytes_(ImuBytes{imu_s, next_imu_->bytes});
      advance_imu();
    }
    if (stopped_) return;
  }
  if (Clock::now() >= next_progress_) print_progress(false);
  boost::asio::post(io_, [self = shared_from_this()] { self->play(); });
}

void Replay::print_progress(bool last) {
  const double wall_s = std::chrono::duration<double>(Clock::now() - wall_start_).count();
  const double data_s = last_record_s_ - first_record_s_;
  const double speed = wall_s > 0 ? data_s / wall_s : 0.0;
  if (last) {
    fmt::print(stderr, "replay: done, {:.1f} s of data in {:.1f} s ({:.1f}x real time)\n", data_s, wall_s, speed);
    return;
  }
  next_progress_ = Clock::now() + kProgressPeriod;
  const double fraction = total_bytes_ > 0 ? std::min(1.0, static_cast<double>(played_bytes_) / total_bytes_) : 0.0;
  const double eta_s = fraction > 0 ? wall_s * (1.0 - fraction) / fraction : 0.0;
  fmt::print(stderr, "replay: {:3.0f}% ({:.1f} s of data, {:.1f}x real time), ETA {:.0f} s\n", fraction * 100, data_s,
             speed, eta_s);
}

void Replay::finish() {
  if (finished_) return;
  finished_ = true;
  if (lidar_.truncated()) spdlog::warn("replay: {}", lidar_.error());
  if (imu_.truncated()) spdlog::warn("replay: {}", imu_.error());
  const double wall_s = std::chrono::duration<double>(Clock::now() - wall_start_).count();
  if (wall_s > 3.0) print_progress(true);
  on_lidar_end_();
  on_imu_end_();
}

}  // namespace tumble::daemon
