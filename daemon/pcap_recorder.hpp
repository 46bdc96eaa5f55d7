// record.dir: the live sensors' bytes as they arrived, in a new directory per
// start (DIR/YYYYmmdd-HHMMSS/{lidar,imu}.pcap), so a restart never overwrites
// a recording. `tumbled --replay` and tumble-dump read them.
#pragma once

#include <memory>
#include <string>

#include "daemon/seams.hpp"
#include "drivers/mti/imu_recording_writer.hpp"
#include "drivers/rs16/lidar_datagram.hpp"
#include "drivers/rs16/recording_writer.hpp"

namespace tumble::daemon {

class PcapRecorder : public Recorder {
 public:
  // Creates the directory and both files; throws std::runtime_error naming the path that failed.
  PcapRecorder(const std::string& dir, const rs16::SourceConfig& ports);
  void record_lidar(const LidarDatagram& datagram) override;
  void record_imu(const ImuBytes& bytes) override;
  void flush() override;

  const std::string& directory() const { return directory_; }

 private:
  std::string directory_;
  rs16::SourceConfig ports_;
  std::unique_ptr<rs16::RecordingWriter> lidar_;
  std::unique_ptr<mti::ImuRecordingWriter> imu_;
};

}  // namespace tumble::daemon
