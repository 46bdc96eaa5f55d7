// Live mode: a scenario played in real time, as the sensors would deliver
// it: MSOP/DIFOP datagrams over UDP and the IMU's bytes into a pty, each at
// its arrival time, paced by CLOCK_MONOTONIC. The run is generated event by
// event as it plays, never held whole in memory.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>

#include "tools/sim/mti_device.hpp"
#include "tools/sim/scenario.hpp"

namespace tumble::sim {

// [at_s, at_s + duration_s) of run time.
struct LiveOutage {
  double at_s = 0.0;
  double duration_s = 0.0;
};

struct LiveOptions {
  std::string host = "127.0.0.1";
  std::uint16_t msop_port = 6699;
  std::uint16_t difop_port = 7788;
  bool allow_remote = false;       // refuse a non-loopback host unless set
  double rate = 1.0;               // 2 = twice real time
  std::optional<double> duration_s;  // play at most this much of the run
  MtiDeviceOptions mti;              // the device on the pty (its baud: the scenario's imu.baud)
  // Run time 0 is when the device first measures (a host configured it), so
  // a configuring host sees the run from its start; nothing is sent before.
  bool start_when_measuring = false;
  // The lidar powers off for the outage and comes back with its header clock
  // a day behind (a unit that lost its time source restarts from its RTC).
  std::optional<LiveOutage> lidar_restart;
  // The MTi is unplugged for the outage: the pty is closed, and a new one
  // (a device at power-on) is made after it.
  std::optional<LiveOutage> imu_unplug;
  // A symbolic link to the pty, re-pointed at each new one, as udev keeps
  // /dev/xsens; announced instead of the pty's own path. Empty: none.
  std::string imu_link;
};

struct LiveSummary {
  std::uint64_t msop_packets = 0;
  std::uint64_t difop_packets = 0;
  std::uint64_t udp_send_failures = 0;
  std::uint64_t imu_reads = 0;
  std::uint64_t imu_bytes = 0;
  std::uint64_t imu_bytes_dropped = 0;  // pty buffer full
  std::uint64_t imu_bytes_held = 0;     // MTData2 not sent: the device was not measuring
  std::uint64_t imu_baud_mismatch_bytes = 0;  // lost: host and device at different speeds
  std::uint64_t mti_requests = 0;       // frames the host sent the device
  std::uint64_t mti_errors_sent = 0;    // answered with Error (MID 0x42)
  std::uint64_t lidar_restart_packets = 0;  // not sent: the lidar was off
  std::uint64_t imu_unplugged_reads = 0;    // not sent: the MTi was unplugged
  std::uint64_t late_events = 0;        // sent more than 1 ms after their time
  double max_late_s = 0.0;              // the worst of them
  bool stopped = false;                 // ended by `stop`, not by the run's end
};

// The pty behaves as an MTi-30 (mti_device.hpp): it answers the host's
// configuration handshake and streams only while measuring.
// Prints "imu-pty <slave path or imu_link>" then "lidar-udp <host> <msop port> <difop port>"
// on `announce` before the first byte goes out. The lidar header clock is set
// to the host's CLOCK_REALTIME at the run's start (a synced lidar at rate 1).
// Throws LiveError / SimConfigError on bad options.
LiveSummary run_live(Scenario scenario, const LiveOptions& options, std::ostream& announce,
                     const std::atomic<bool>& stop);

}  // namespace tumble::sim
