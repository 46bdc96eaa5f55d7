#include "drivers/mti/imu_recording_writer.hpp"

namespace tumble::mti {

ImuRecordingWriter::ImuRecordingWriter(const std::string& path) : writer_(path, pcap::kLinkUser0) {}

void ImuRecordingWriter::write(std::int64_t arrival_ns, std::span<const std::uint8_t> read) {
  writer_.write(arrival_ns, read);
}

}  // namespace tumble::mti
