// An MTi recording (our LINKTYPE_USER0 pcap or a raw Xbus byte stream) as CSV
// (one row per IMU sample) or as a summary of what the driver counted.
#pragma once

#include <cstdio>
#include <string>

#include "drivers/mti/mti_stream.hpp"

namespace tumble::dump {

struct MtiDumpOptions {
  mti::MtiStreamOptions stream;
  bool summary = false;
};

// Throws std::invalid_argument for bad options and std::runtime_error when the
// file cannot be read. Returns the recording's problem() after the output was
// written, or an empty string for a clean file.
std::string dump_mti(const std::string& path, const MtiDumpOptions& options, std::FILE* out);

}  // namespace tumble::dump
