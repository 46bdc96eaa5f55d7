// --replay: the lidar pcap and the IMU pcap played through the pipeline's
// seams, merged in record-time order on the io thread (the pipeline relies on
// that order for a lossless, deterministic `--rate max`). At a finite rate,
// records leave when their recorded time is due on the steady clock, scaled.
// Replays longer than a few seconds print their progress with an ETA.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "daemon/command_line.hpp"
#include "daemon/config.hpp"
#include "daemon/seams.hpp"
#include "drivers/pcap/pcap_file.hpp"
#include "drivers/rs16/pcap_source.hpp"

namespace tumble::daemon {

class Replay : public std::enable_shared_from_this<Replay> {
 public:
  // Opens both files; throws std::runtime_error naming a file that cannot be
  // read or is not the expected kind of recording.
  Replay(boost::asio::io_context& io, const ReplayFiles& files, const LidarConfig& lidar, ReplayRate rate);

  // The two seams; playing starts once both are started.
  std::unique_ptr<LidarDatagramSource> lidar_source();
  std::unique_ptr<ImuByteSource> imu_source();

 private:
  class LidarEnd;
  class ImuEnd;
  using Clock = std::chrono::steady_clock;

  void started();
  void stop();
  void play();
  void advance_lidar();
  void advance_imu();
  void finish();
  void print_progress(bool last);

  boost::asio::io_context& io_;
  ReplayFiles files_;
  ReplayRate rate_;
  rs16::SourceConfig ports_;
  rs16::PcapSource lidar_;
  pcap::Reader imu_;
  boost::asio::steady_timer timer_;

  std::function<void(const LidarDatagram&)> on_datagram_;
  std::function<void()> on_lidar_end_;
  std::function<void(const ImuBytes&)> on_bytes_;
  std::function<void()> on_imu_end_;
  int starts_ = 0;
  bool stopped_ = false;
  bool finished_ = false;

  std::optional<rs16::LidarDatagram> next_lidar_;
  std::optional<pcap::Record> next_imu_;
  double first_record_s_ = 0.0;
  double last_record_s_ = 0.0;
  Clock::time_point wall_start_;
  Clock::time_point next_progress_;
  std::uintmax_t total_bytes_ = 0;
  std::uintmax_t played_bytes_ = 0;
};

}  // namespace tumble::daemon
