// The one place where tumbled's configuration becomes the parameters of the
// core and the drivers: every key of config/tumbled.yaml that is not the
// daemon's own lands here in exactly one field.
#pragma once

#include "core/scan_registration.hpp"
#include "daemon/config.hpp"
#include "daemon/imu_sample_check.hpp"
#include "drivers/mti/mti_stream.hpp"
#include "drivers/mti/serial_source.hpp"
#include "drivers/rs16/decoder.hpp"
#include "drivers/rs16/lidar_datagram.hpp"
#include "drivers/rs16/scan_assembler.hpp"

namespace tumble::daemon {

OdometryParams odometry_params(const DaemonConfig& config);

rs16::DecoderConfig lidar_decoder_config(const LidarConfig& lidar);
rs16::SourceConfig lidar_source_config(const LidarConfig& lidar);
rs16::ScanAssemblerConfig scan_assembler_config(const LidarConfig& lidar);

mti::MtiStreamOptions imu_stream_options(const ImuConfig& imu);
mti::SerialSourceOptions serial_source_options(const ImuConfig& imu);
ImuLimits imu_limits(const ImuConfig& imu);

}  // namespace tumble::daemon
