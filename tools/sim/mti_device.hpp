// The MTi-30's side of the configuration handshake (docs/sensors.md, MT0101P): it reads
// the host's Xbus requests with the driver's own frame reader and answers them
// with the driver's encoders, after a reply latency, as the device does:
// GoToConfig, ReqDID, ReqProductCode, ReqFWRev, SetOutputConfiguration (echoed),
// SetBaudrate (effective after Reset), Reset (then WakeUp), GoToMeasurement,
// and Error (MID 0x42) for what it refuses. It does no I/O and reads no clock:
// `tumble-sim live` feeds it the pty's bytes and sends what it answers.
// Misbehaviour on request: silent, late, a wrong product code, an error for
// one request, already streaming when the host opens the port.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "drivers/mti/frame_reader.hpp"
#include "drivers/mti/output_configuration.hpp"

namespace tumble::sim {

enum class MtiStartState : std::uint8_t {
  Measuring,  // powered up long before: streaming MTData2 (nobody acknowledged its WakeUp)
  Config,     // waiting in config state for requests
  WakeUp,     // powers up with the run: WakeUp, measuring unless acknowledged within 0.5 s
};

struct MtiDeviceOptions {
  MtiStartState start = MtiStartState::Measuring;
  std::string product_code = "MTi-30-2A8G4";
  std::uint32_t device_id = 0x03700123;
  std::uint32_t baud = 115200;
  double reply_latency_s = 0.002;  // request received -> first byte of the answer
  bool silent = false;             // answers nothing, never streams
  // Request MID answered with Error (MID 0x42) and this code instead.
  std::optional<std::uint8_t> refuse_mid{};
  std::uint8_t refuse_code = 33;  // parameter invalid
  double reset_s = 0.4;           // Reset -> WakeUp at the new baud
  double wake_up_ack_window_s = 0.5;
};

// "measuring", "config", "wake-up"; nullopt for other text.
std::optional<MtiStartState> parse_mti_start_state(const std::string& text);

struct MtiDeviceCounts {
  std::uint64_t requests = 0;  // frames from the host
  std::uint64_t errors_sent = 0;
  std::uint64_t host_bytes_discarded = 0;  // not part of a good frame
};

class MtiDevice {
 public:
  explicit MtiDevice(MtiDeviceOptions options, double now_s = 0.0);

  // Bytes the host wrote, read at device time now_s.
  void on_host_bytes(std::span<const std::uint8_t> bytes, double now_s);
  // Answers (and the power-up WakeUp) due by now_s, in order; state changes
  // they carry (measuring, a new baud) take effect as they go out.
  void take_due(double now_s, std::vector<std::uint8_t>& out);
  // When the next answer or timeout falls due; nullopt when none is pending.
  std::optional<double> next_due_s() const;

  bool measuring() const { return measuring_; }
  std::uint32_t baud() const { return baud_; }
  // The output list the host set (empty until it set one).
  const std::vector<mti::OutputSetting>& output_configuration() const { return output_configuration_; }
  const MtiDeviceCounts& counts() const { return counts_; }

 private:
  enum class After : std::uint8_t { Nothing, StartMeasuring, StopMeasuring, PowerUp };
  struct Pending {
    double due_s;
    std::vector<std::uint8_t> bytes;
    After after = After::Nothing;
  };

  void answer(std::uint8_t mid, std::span<const std::uint8_t> payload, double now_s);
  void reply(std::uint8_t mid, std::span<const std::uint8_t> payload, double now_s, After after = After::Nothing);
  void refuse(std::uint8_t code, double now_s);
  void power_up(double now_s);

  MtiDeviceOptions options_;
  mti::FrameReader reader_;
  std::deque<Pending> pending_;
  std::vector<mti::OutputSetting> output_configuration_;
  std::uint32_t baud_;
  std::optional<std::uint32_t> baud_after_reset_;
  std::optional<double> wake_up_deadline_s_;  // measuring unless WakeUpAck by then
  bool measuring_ = false;
  MtiDeviceCounts counts_;
};

}  // namespace tumble::sim
