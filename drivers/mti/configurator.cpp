#include "drivers/mti/configurator.hpp"

#include <cstdio>
#include <stdexcept>

#include "drivers/mti/baud.hpp"
#include "drivers/mti/commands.hpp"
#include "drivers/mti/device_error.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_encode.hpp"

namespace tumble::mti {
namespace {

constexpr std::uint16_t kMaxImuRateHz = 400;

std::string seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", s);
  return text;
}

}  // namespace

std::string_view config_step_name(ConfigStep step) {
  switch (step) {
    case ConfigStep::GoToConfig: return "GoToConfig";
    case ConfigStep::ReqDeviceId: return "ReqDID";
    case ConfigStep::ReqProductCode: return "ReqProductCode";
    case ConfigStep::ReqFirmwareRev: return "ReqFWRev";
    case ConfigStep::SetBaudrate: return "SetBaudrate";
    case ConfigStep::Reset: return "Reset";
    case ConfigStep::AwaitWakeUp: return "waiting for WakeUp";
    case ConfigStep::SetOutputConfiguration: return "SetOutputConfiguration";
    case ConfigStep::GoToMeasurement: return "GoToMeasurement";
    case ConfigStep::Measuring: return "measuring";
    case ConfigStep::ReadOnly: return "read-only";
    case ConfigStep::Failed: return "failed";
  }
  return "?";
}

std::size_t configured_frame_bytes(NumberFormat format) {
  const std::size_t payload = encode_mtdata2(MtData2Out{}, format).size();
  return (payload <= kMaxStandardPayloadBytes ? 4 : 6) + payload + 1;
}

Configurator::Configurator(ConfiguratorOptions options)
    : options_(options), line_baud_(options.baud) {
  if (!options_.configure) return;  // nothing is sent, so nothing to check
  if (options_.imu_rate_hz < 1 || options_.imu_rate_hz > kMaxImuRateHz)
    throw std::invalid_argument("mti: imu rate " + std::to_string(options_.imu_rate_hz) + " Hz is outside 1.." +
                                std::to_string(kMaxImuRateHz));
  if (options_.set_baud != 0 && !baud_code(options_.set_baud))
    throw std::invalid_argument("mti: the MTi has no code for " + std::to_string(options_.set_baud) + " baud");
  const std::uint32_t target_baud = options_.set_baud != 0 ? options_.set_baud : options_.baud;
  const std::string problem =
      baud_problem(target_baud, configured_frame_bytes(options_.format), options_.imu_rate_hz);
  if (!problem.empty()) throw std::invalid_argument("mti: " + problem);
  requested_ = imu_output_configuration(options_.imu_rate_hz, options_.format);
}

void Configurator::start(double now_s) {
  error_.clear();
  device_ = {};
  output_.clear();
  baud_switch_.reset();
  measurement_started_ = false;
  line_baud_ = options_.baud;
  tried_new_baud_ = false;
  if (!options_.configure) {
    step_ = ConfigStep::ReadOnly;
    return;
  }
  enter(ConfigStep::GoToConfig, now_s);
}

void Configurator::enter(ConfigStep step, double now_s) {
  step_ = step;
  const bool go_to_config = step == ConfigStep::GoToConfig;
  const double retry_s = go_to_config ? options_.go_to_config_retry_s : options_.reply_retry_s;
  double timeout_s = go_to_config ? options_.go_to_config_timeout_s : options_.reply_timeout_s;
  if (step == ConfigStep::AwaitWakeUp) timeout_s = options_.wake_up_timeout_s;
  deadline_s_ = now_s + timeout_s;
  next_send_s_ = now_s + retry_s;
  send_request();
}

void Configurator::send_request() {
  std::vector<std::uint8_t> frame;
  switch (step_) {
    case ConfigStep::GoToConfig: frame = encode_go_to_config(); break;
    case ConfigStep::ReqDeviceId: frame = encode_req_device_id(); break;
    case ConfigStep::ReqProductCode: frame = encode_req_product_code(); break;
    case ConfigStep::ReqFirmwareRev: frame = encode_req_firmware_rev(); break;
    case ConfigStep::SetBaudrate: frame = encode_set_baudrate(options_.set_baud); break;
    case ConfigStep::Reset: frame = encode_reset(); break;
    case ConfigStep::SetOutputConfiguration: frame = encode_set_output_configuration(requested_); break;
    case ConfigStep::GoToMeasurement: frame = encode_go_to_measurement(); break;
    default: return;
  }
  output_.insert(output_.end(), frame.begin(), frame.end());
}

void Configurator::fail(std::string why) {
  step_ = ConfigStep::Failed;
  error_ = std::move(why);
}

void Configurator::on_tick(double now_s) {
  switch (step_) {
    case ConfigStep::Measuring:
    case ConfigStep::ReadOnly:
    case ConfigStep::Failed: return;
    default: break;
  }
  if (now_s >= deadline_s_) {
    if (step_ == ConfigStep::GoToConfig) {
      if (options_.set_baud != 0 && !tried_new_baud_ && line_baud_ != options_.set_baud) {
        // The device may already run at the new baud (set in an earlier run).
        tried_new_baud_ = true;
        line_baud_ = options_.set_baud;
        baud_switch_ = line_baud_;
        enter(ConfigStep::GoToConfig, now_s);
        return;
      }
      fail("no GoToConfigAck within " + seconds(options_.go_to_config_timeout_s) + " at " +
           std::to_string(line_baud_) + " baud: is the MTi connected, powered and at this baud?");
    } else if (step_ == ConfigStep::AwaitWakeUp) {
      fail("the MTi did not come back (no WakeUp) within " + seconds(options_.wake_up_timeout_s) +
           " of its reset to " + std::to_string(line_baud_) + " baud");
    } else {
      fail("no reply to " + std::string(config_step_name(step_)) + " within " + seconds(options_.reply_timeout_s));
    }
    return;
  }
  if (now_s >= next_send_s_) {
    send_request();
    next_send_s_ = now_s + (step_ == ConfigStep::GoToConfig ? options_.go_to_config_retry_s : options_.reply_retry_s);
  }
}

void Configurator::on_frame(const XbusFrame& frame, double now_s) {
  if (step_ == ConfigStep::ReadOnly || step_ == ConfigStep::Failed) return;
  if (frame.mid == mid::kWakeUp) {
    // Acknowledged in time, the device stays in config state: start over.
    const auto ack = encode_wake_up_ack();
    output_.insert(output_.end(), ack.begin(), ack.end());
    enter(ConfigStep::GoToConfig, now_s);
    return;
  }
  if (step_ == ConfigStep::Measuring) return;
  if (frame.mid == mid::kError) {
    fail("the MTi answered " + std::string(config_step_name(step_)) + " with " + describe_error(frame.payload));
    return;
  }
  on_reply(frame, now_s);
}

void Configurator::on_reply(const XbusFrame& frame, double now_s) {
  switch (step_) {
    case ConfigStep::GoToConfig:
      if (frame.mid == mid::kGoToConfigAck) enter(ConfigStep::ReqDeviceId, now_s);
      return;
    case ConfigStep::ReqDeviceId:
      if (frame.mid != mid::kDeviceId) return;
      device_.device_id = parse_device_id(frame.payload);
      enter(ConfigStep::ReqProductCode, now_s);
      return;
    case ConfigStep::ReqProductCode:
      if (frame.mid != mid::kProductCode) return;
      device_.product_code = parse_product_code(frame.payload);
      device_.ranges = ranges_from_product_code(device_.product_code);
      enter(ConfigStep::ReqFirmwareRev, now_s);
      return;
    case ConfigStep::ReqFirmwareRev:
      if (frame.mid != mid::kFirmwareRev) return;
      if (const auto fw = parse_firmware_revision(frame.payload)) device_.firmware = fw->text();
      after_firmware(now_s);
      return;
    case ConfigStep::SetBaudrate:
      if (frame.mid == mid::kSetBaudrateAck) enter(ConfigStep::Reset, now_s);
      return;
    case ConfigStep::Reset:
      if (frame.mid != mid::kResetAck) return;
      // The new baud takes effect as the device restarts; it then sends WakeUp.
      line_baud_ = options_.set_baud;
      baud_switch_ = line_baud_;
      enter(ConfigStep::AwaitWakeUp, now_s);
      return;
    case ConfigStep::SetOutputConfiguration: {
      if (frame.mid != mid::kOutputConfiguration) return;
      std::vector<OutputSetting> effective;
      try {
        effective = parse_output_configuration(frame.payload);
      } catch (const std::invalid_argument& e) {
        fail(std::string("the MTi's OutputConfiguration reply is malformed: ") + e.what());
        return;
      }
      if (effective != requested_) {
        fail("the MTi did not take the output configuration: asked " + describe(requested_) + "; it uses " +
             describe(effective));
        return;
      }
      enter(ConfigStep::GoToMeasurement, now_s);
      return;
    }
    case ConfigStep::GoToMeasurement:
      if (frame.mid != mid::kGoToMeasurementAck) return;
      step_ = ConfigStep::Measuring;
      measurement_started_ = true;
      return;
    default: return;
  }
}

void Configurator::after_firmware(double now_s) {
  if (options_.set_baud != 0 && line_baud_ != options_.set_baud)
    enter(ConfigStep::SetBaudrate, now_s);
  else
    enter(ConfigStep::SetOutputConfiguration, now_s);
}

std::vector<std::uint8_t> Configurator::take_output() {
  std::vector<std::uint8_t> out;
  out.swap(output_);
  return out;
}

std::optional<std::uint32_t> Configurator::take_baud_switch() {
  auto b = baud_switch_;
  baud_switch_.reset();
  return b;
}

bool Configurator::take_measurement_started() {
  const bool started = measurement_started_;
  measurement_started_ = false;
  return started;
}

}  // namespace tumble::mti
