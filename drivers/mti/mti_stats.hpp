// What the MTi driver counted: every byte, frame and message is accounted for.
#pragma once

#include <array>
#include <cstdint>

#include "drivers/mti/frame_reader.hpp"
#include "drivers/mti/mtdata2_decode.hpp"

namespace tumble::mti {

struct MtiStats {
  FrameReaderStats frames;        // bytes, good frames, bad frames by reason
  MtData2DecodeStats mtdata2;     // MTData2 messages and skipped packets
  std::uint64_t imu_samples = 0;  // delivered
  std::uint64_t non_imu_messages = 0;          // MTData2 without IMU data (GNSS and other outputs)
  std::uint64_t other_frames = 0;              // frames that are not MTData2 (acks, replies, errors)
  std::uint64_t device_errors = 0;             // Error (MID 0x42) frames
  std::uint64_t discarded_while_configuring = 0;  // MTData2 before GoToMeasurement was acknowledged
  std::uint64_t stale_samples_dropped = 0;     // the first sample after GoToMeasurement
  std::uint64_t packet_counter_gaps = 0;       // breaks in PacketCounter
  std::uint64_t missing_packets = 0;           // packets those breaks skipped
  std::uint64_t duplicate_frames = 0;          // MTData2 repeating the newest PacketCounter: dropped
  std::uint64_t out_of_order_frames = 0;       // MTData2 with an older PacketCounter (arrived late): dropped
  std::uint64_t sample_time_gaps = 0;          // IMU samples more than 1.5 periods after the previous
  std::uint64_t sample_time_backwards = 0;     // IMU samples not after the previous: dropped
  std::uint64_t sensor_clock_restarts = 0;     // SampleTimeFine jumped back: device reset, mapping restarted
  std::uint64_t samples_without_sample_time = 0;  // timed by arrival (or dropped without arrival times)
  std::uint64_t clipped_samples = 0;           // samples with any clip flag
  std::array<std::uint64_t, 3> accel_saturated{};  // per axis X Y Z
  std::array<std::uint64_t, 3> gyro_saturated{};
};

}  // namespace tumble::mti
