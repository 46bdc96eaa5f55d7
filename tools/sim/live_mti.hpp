// The simulated MTi on the live pty: while live mode waits for its next
// event it reads what the host wrote, lets the device model answer in real
// time, and passes the scenario's MTData2 stream only while the device
// measures. The line speed is the pty's: bytes sent while the host's termios
// speed differs from the device's baud are lost (a real UART would read
// garbage), and counted.
#pragma once

#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include "tools/sim/live_sinks.hpp"
#include "tools/sim/mti_device.hpp"

namespace tumble::sim {

struct LiveMtiCounts {
  std::uint64_t stream_bytes_held = 0;     // MTData2 bytes not sent: the device was not measuring
  std::uint64_t baud_mismatch_bytes = 0;   // lost both ways: host and device at different speeds
  std::uint64_t reply_bytes = 0;           // answers and WakeUps sent
};

class LiveMti {
 public:
  // start_mono_ns: CLOCK_MONOTONIC at device time 0.
  LiveMti(ImuPty& pty, const MtiDeviceOptions& options, std::int64_t start_mono_ns);

  // Sleeps until due_ns (CLOCK_MONOTONIC), answering the host meanwhile.
  // False when `stop` was raised first.
  bool wait_until(std::int64_t due_ns, const std::atomic<bool>& stop);
  // One read of the scenario's MTData2 stream: out only while the device measures.
  void stream(std::span<const std::uint8_t> bytes);

  const MtiDevice& device() const { return device_; }
  const LiveMtiCounts& counts() const { return counts_; }

 private:
  double device_time_s(std::int64_t mono_ns) const;
  bool line_speeds_match() const;
  void serve(std::int64_t now_ns);
  void send(std::span<const std::uint8_t> bytes);

  ImuPty& pty_;
  MtiDevice device_;
  std::int64_t start_mono_ns_;
  std::vector<std::uint8_t> host_bytes_;
  std::vector<std::uint8_t> replies_;
  LiveMtiCounts counts_;
};

}  // namespace tumble::sim
