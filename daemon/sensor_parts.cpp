#include "daemon/sensor_parts.hpp"

#include <memory>
#include <string>

#include <spdlog/spdlog.h>

#include "daemon/core_stages.hpp"
#include "daemon/driver_params.hpp"
#include "daemon/imu_parts.hpp"
#include "daemon/lidar_parts.hpp"
#include "daemon/pcap_recorder.hpp"
#include "daemon/replay.hpp"
#include "daemon/thread_setup.hpp"

namespace tumble::daemon {

PipelineParts make_sensor_parts(boost::asio::io_context& io, const DaemonConfig& config, const RunOptions& options) {
  const OdometryParams params = odometry_params(config);
  PipelineParts parts;
  parts.fuser = std::make_unique<CoreFuserStage>(params);
  const int nice = config.daemon.registration_nice;
  parts.registration = std::make_unique<CoreRegistrationStage>(
      params, scan_assembler_config(config.lidar), config.daemon.health.lidar_silent_to_lost_s,
      static_cast<std::size_t>(config.daemon.registration_threads),
      [nice](std::size_t helper) {
        const std::string name = "tumble-reg-" + std::to_string(helper);
        name_this_thread(name);
        if (const std::string error = lower_this_thread_priority(nice); !error.empty())
          spdlog::warn("{}: {}", name, error);
      });
  parts.lidar_decoder = std::make_unique<Rs16LidarDecoder>(config.lidar);
  if (options.replay) {
    const auto replay = std::make_shared<Replay>(io, *options.replay, config.lidar, options.rate);
    parts.lidar_source = replay->lidar_source();
    parts.imu_source = replay->imu_source();
    parts.imu_decoder = std::make_unique<MtiByteDecoder>(config.imu);
    return parts;
  }
  auto reads = std::make_shared<SerialReads>();
  parts.lidar_source = std::make_unique<LiveLidarSource>(io, config.lidar);
  parts.imu_source = std::make_unique<LiveImuSource>(io, config.imu, reads);
  parts.imu_decoder = std::make_unique<SerialSampleDecoder>(config.imu, reads);
  if (!config.record.dir.empty())
    parts.recorder =
        std::make_unique<PcapRecorder>(config.record, lidar_source_config(config.lidar), config.daemon.checkpoint_period_s);
  return parts;
}

}  // namespace tumble::daemon
