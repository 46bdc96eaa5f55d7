// An RS-16 pcap as CSV (one row per point of every assembled scan) or as a
// summary of what the driver counted.
#pragma once

#include <cstdio>
#include <string>

#include "drivers/rs16/driver.hpp"
#include "drivers/rs16/lidar_datagram.hpp"

namespace tumble::dump {

struct Rs16DumpOptions {
  rs16::SourceConfig source;
  rs16::DriverConfig driver;
  bool summary = false;
};

// Throws std::invalid_argument for bad options and pcap::Error when the file
// cannot be replayed. Returns what was wrong with the recording after the
// output was written (truncation), or an empty string.
std::string dump_rs16(const std::string& path, const Rs16DumpOptions& options, std::FILE* out);

}  // namespace tumble::dump
