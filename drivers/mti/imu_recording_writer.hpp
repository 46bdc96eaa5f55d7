// Records the IMU serial stream for replay: a pcap file, LINKTYPE_USER0, one
// record per serial read, stamped with its host arrival time (CLOCK_REALTIME,
// ns), on the same clock as the lidar pcap. tcpdump and tshark can list it.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "drivers/pcap/pcap_file.hpp"

namespace tumble::mti {

class ImuRecordingWriter {
 public:
  // Creates (truncates) path; throws pcap::Error naming it when it cannot.
  explicit ImuRecordingWriter(const std::string& path);
  void write(std::int64_t arrival_ns, std::span<const std::uint8_t> read);
  void flush() { writer_.flush(); }
  void close() { writer_.close(); }
  // The file itself: its size, errors and sync.
  pcap::Writer& file() { return writer_; }

 private:
  pcap::Writer writer_;
};

}  // namespace tumble::mti
