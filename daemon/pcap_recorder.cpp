#include "daemon/pcap_recorder.hpp"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>

namespace tumble::daemon {

namespace {

std::string new_recording_directory(const std::string& dir) {
  const auto now = std::chrono::floor<std::chrono::seconds>(std::chrono::system_clock::now());
  std::filesystem::path path = std::filesystem::path(dir) / fmt::format("{:%Y%m%d-%H%M%S}", now);
  for (int suffix = 1; std::filesystem::exists(path); ++suffix)
    path = std::filesystem::path(dir) / fmt::format("{:%Y%m%d-%H%M%S}-{}", now, suffix);
  std::error_code error;
  std::filesystem::create_directories(path, error);
  if (error) throw std::runtime_error(fmt::format("record.dir: cannot create {}: {}", path.string(), error.message()));
  return path.string();
}

std::int64_t to_ns(double t_s) { return std::llround(t_s * 1e9); }

}  // namespace

PcapRecorder::PcapRecorder(const std::string& dir, const rs16::SourceConfig& ports)
    : directory_(new_recording_directory(dir)), ports_(ports) {
  rs16::RecordingAddresses addresses;
  addresses.msop_port = ports.msop_port;
  addresses.difop_port = ports.difop_port;
  lidar_ = std::make_unique<rs16::RecordingWriter>(directory_ + "/lidar.pcap", addresses);
  imu_ = std::make_unique<mti::ImuRecordingWriter>(directory_ + "/imu.pcap");
  spdlog::info("recording the sensors into {}", directory_);
}

void PcapRecorder::record_lidar(const LidarDatagram& datagram) {
  const rs16::PacketKind kind =
      datagram.dst_port == ports_.difop_port ? rs16::PacketKind::Difop : rs16::PacketKind::Msop;
  lidar_->write(to_ns(datagram.arrival_s), kind, datagram.payload);
}

void PcapRecorder::record_imu(const ImuBytes& bytes) { imu_->write(to_ns(bytes.arrival_s), bytes.bytes); }

void PcapRecorder::flush() {
  lidar_->flush();
  imu_->flush();
}

}  // namespace tumble::daemon
