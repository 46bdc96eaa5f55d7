// Configures an MTi as a state machine driven by bytes in and bytes out: it
// does no I/O and reads no clock (time comes in as data), so a scripted fake
// device can drive it in a unit test.
//
// GoToConfig (retried every 100 ms for up to 2 s) -> ReqDID -> ReqProductCode
// -> ReqFWRev -> [SetBaudrate -> Reset -> WakeUp at the new baud -> GoToConfig
// ...] -> SetOutputConfiguration (the echoed, effective list must equal the
// request) -> GoToMeasurement -> measuring. A WakeUp at any time (the device
// restarted) is acknowledged and the sequence starts again. Read-only mode
// sends nothing and takes whatever MTData2 arrives.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "drivers/mti/number_format.hpp"
#include "drivers/mti/output_configuration.hpp"
#include "drivers/mti/product_code.hpp"
#include "drivers/mti/xbus_frame.hpp"

namespace tumble::mti {

enum class ConfigStep : std::uint8_t {
  GoToConfig,
  ReqDeviceId,
  ReqProductCode,
  ReqFirmwareRev,
  SetBaudrate,
  Reset,
  AwaitWakeUp,
  SetOutputConfiguration,
  GoToMeasurement,
  Measuring,
  ReadOnly,
  Failed,
};
std::string_view config_step_name(ConfigStep step);

struct ConfiguratorOptions {
  bool configure = true;         // false: read-only, nothing is sent
  std::uint16_t imu_rate_hz = 100;  // 1..400
  NumberFormat format = NumberFormat::Float32;
  std::uint32_t baud = 115200;   // the baud the device is expected at
  std::uint32_t set_baud = 0;    // 0: keep; else move the device (SetBaudrate + Reset) to this
  double go_to_config_retry_s = 0.1;
  double go_to_config_timeout_s = 2.0;
  double reply_retry_s = 0.5;
  double reply_timeout_s = 2.0;
  double wake_up_timeout_s = 5.0;  // for the device to restart after Reset
};

struct DeviceInfo {
  std::optional<std::uint32_t> device_id;
  std::string product_code;
  std::string firmware;
  SensorRanges ranges;
};

// Bytes of one MTData2 frame with the outputs the configurator asks for.
std::size_t configured_frame_bytes(NumberFormat format);

class Configurator {
 public:
  // Throws std::invalid_argument for a rate outside 1..400 Hz, a baud rate the
  // MTi has no code for, or a baud too low for the rate.
  explicit Configurator(ConfiguratorOptions options);

  // (Re)starts the sequence at the options' baud.
  void start(double now_s);
  void on_frame(const XbusFrame& frame, double now_s);
  // Retries and timeouts; call every few tens of ms while configuring.
  void on_tick(double now_s);

  // Bytes to write to the device, in order; cleared by taking them.
  std::vector<std::uint8_t> take_output();
  // The baud the host port must switch to now (after ResetAck, or to try the
  // new baud when the device is silent at the old one).
  std::optional<std::uint32_t> take_baud_switch();
  // True once after GoToMeasurementAck: the next sample is stale.
  bool take_measurement_started();

  ConfigStep step() const { return step_; }
  bool measuring() const { return step_ == ConfigStep::Measuring || step_ == ConfigStep::ReadOnly; }
  bool failed() const { return step_ == ConfigStep::Failed; }
  const std::string& error() const { return error_; }
  const DeviceInfo& device() const { return device_; }
  std::uint32_t line_baud() const { return line_baud_; }
  const std::vector<OutputSetting>& requested_output() const { return requested_; }

 private:
  void enter(ConfigStep step, double now_s);
  void send_request();
  void fail(std::string why);
  void on_reply(const XbusFrame& frame, double now_s);
  void after_firmware(double now_s);

  ConfiguratorOptions options_;
  std::vector<OutputSetting> requested_;
  ConfigStep step_ = ConfigStep::GoToConfig;
  std::uint32_t line_baud_ = 0;
  bool tried_new_baud_ = false;
  double next_send_s_ = 0;
  double deadline_s_ = 0;
  std::string error_;
  DeviceInfo device_;
  std::vector<std::uint8_t> output_;
  std::optional<std::uint32_t> baud_switch_;
  bool measurement_started_ = false;
};

}  // namespace tumble::mti
