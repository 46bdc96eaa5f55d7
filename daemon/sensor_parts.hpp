// Builds the pipeline's parts from the drivers and the core for this run:
// live (UDP + serial, optionally recording) or a replay of two pcaps.
#pragma once

#include <boost/asio/io_context.hpp>

#include "daemon/config.hpp"
#include "daemon/pipeline.hpp"
#include "daemon/run.hpp"

namespace tumble::daemon {

// Throws std::runtime_error naming what could not be opened (a pcap, a socket,
// the recording directory) and std::invalid_argument for inconsistent parameters.
PipelineParts make_sensor_parts(boost::asio::io_context& io, const DaemonConfig& config, const RunOptions& options);

}  // namespace tumble::daemon
