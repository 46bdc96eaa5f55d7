#include "tools/sim/mti_device.hpp"

#include <algorithm>

#include "drivers/mti/baud.hpp"
#include "drivers/mti/big_endian.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/xbus_frame.hpp"

namespace tumble::sim {
namespace {

// Error codes (MT0101P) the device answers with.
constexpr std::uint8_t kErrorPeriodInvalid = 3;
constexpr std::uint8_t kErrorMessageInvalid = 4;
constexpr std::uint8_t kErrorBaudRateInvalid = 32;

constexpr std::uint16_t kMaxOutputRateHz = 400;

// FirmwareRev as the MTi-300 fixture answers it: 1.8.2 build 37 rev 70964.
constexpr std::uint8_t kFirmwareRevision[] = {0x01, 0x08, 0x02, 0x00, 0x00, 0x00, 0x25, 0x00, 0x01, 0x15, 0x34};

// The device runs its outputs at divisors of 400 Hz: a rate between two is
// taken down to the next one, and the echo says so.
std::uint16_t effective_rate_hz(std::uint16_t rate_hz) {
  if (rate_hz == mti::kRateEveryMessage) return rate_hz;
  std::uint16_t r = std::min(rate_hz, kMaxOutputRateHz);
  while (kMaxOutputRateHz % r != 0) --r;
  return r;
}

}  // namespace

std::optional<MtiStartState> parse_mti_start_state(const std::string& text) {
  if (text == "measuring") return MtiStartState::Measuring;
  if (text == "config") return MtiStartState::Config;
  if (text == "wake-up") return MtiStartState::WakeUp;
  return std::nullopt;
}

MtiDevice::MtiDevice(MtiDeviceOptions options, double now_s) : options_(std::move(options)), baud_(options_.baud) {
  if (options_.silent) return;
  if (options_.start == MtiStartState::Measuring) measuring_ = true;
  if (options_.start == MtiStartState::WakeUp) power_up(now_s);
}

void MtiDevice::power_up(double now_s) {
  measuring_ = false;
  pending_.push_back({now_s, mti::encode_xbus_frame(mti::mid::kWakeUp, {})});
  wake_up_deadline_s_ = now_s + options_.wake_up_ack_window_s;
}

void MtiDevice::on_host_bytes(std::span<const std::uint8_t> bytes, double now_s) {
  reader_.push(bytes);
  while (const auto frame = reader_.next()) {
    ++counts_.requests;
    if (!options_.silent) answer(frame->mid, frame->payload, now_s);
  }
  counts_.host_bytes_discarded = reader_.stats().bytes_discarded;
}

void MtiDevice::reply(std::uint8_t mid, std::span<const std::uint8_t> payload, double now_s, After after) {
  pending_.push_back({now_s + options_.reply_latency_s, mti::encode_xbus_frame(mid, payload), after});
}

void MtiDevice::refuse(std::uint8_t code, double now_s) {
  ++counts_.errors_sent;
  const std::uint8_t payload[] = {code};
  reply(mti::mid::kError, payload, now_s);
}

void MtiDevice::answer(std::uint8_t mid, std::span<const std::uint8_t> payload, double now_s) {
  namespace m = mti::mid;
  if (mid == m::kWakeUpAck) {
    wake_up_deadline_s_.reset();  // acknowledged in time: stays in config state
    return;
  }
  if (options_.refuse_mid && mid == *options_.refuse_mid) {
    refuse(options_.refuse_code, now_s);
    return;
  }
  // While measuring the device takes only what ends or restarts measurement.
  if (measuring_ && mid != m::kGoToConfig && mid != m::kReset && mid != m::kGoToMeasurement) {
    refuse(kErrorMessageInvalid, now_s);
    return;
  }
  switch (mid) {
    case m::kGoToConfig: reply(m::kGoToConfigAck, {}, now_s, After::StopMeasuring); return;
    case m::kGoToMeasurement: reply(m::kGoToMeasurementAck, {}, now_s, After::StartMeasuring); return;
    case m::kReqDeviceId: {
      std::vector<std::uint8_t> id;
      mti::append_u32_be(id, options_.device_id);
      reply(m::kDeviceId, id, now_s);
      return;
    }
    case m::kReqProductCode: {
      const std::vector<std::uint8_t> code(options_.product_code.begin(), options_.product_code.end());
      reply(m::kProductCode, code, now_s);
      return;
    }
    case m::kReqFirmwareRev: reply(m::kFirmwareRev, kFirmwareRevision, now_s); return;
    case m::kSetOutputConfiguration: {
      if (payload.empty() || payload.size() % 4 != 0) {
        refuse(kErrorMessageInvalid, now_s);
        return;
      }
      std::vector<mti::OutputSetting> effective = mti::parse_output_configuration(payload);
      for (mti::OutputSetting& s : effective) {
        if (s.rate_hz == 0) {
          refuse(kErrorPeriodInvalid, now_s);
          return;
        }
        s.rate_hz = effective_rate_hz(s.rate_hz);
      }
      output_configuration_ = effective;
      reply(m::kOutputConfiguration, mti::encode_output_configuration(effective), now_s);
      return;
    }
    case m::kSetBaudrate: {
      const std::uint8_t current[] = {mti::baud_code(baud_).value_or(0)};
      if (payload.empty()) {  // a request for the current baud
        reply(m::kSetBaudrateAck, current, now_s);
        return;
      }
      const auto baud = payload.size() == 1 ? mti::baud_from_code(payload[0]) : std::nullopt;
      if (!baud) {
        refuse(kErrorBaudRateInvalid, now_s);
        return;
      }
      baud_after_reset_ = *baud;  // takes effect after Reset
      reply(m::kSetBaudrateAck, {}, now_s);
      return;
    }
    case m::kReset: reply(m::kResetAck, {}, now_s, After::PowerUp); return;
    default: refuse(kErrorMessageInvalid, now_s); return;
  }
}

void MtiDevice::take_due(double now_s, std::vector<std::uint8_t>& out) {
  if (wake_up_deadline_s_ && now_s >= *wake_up_deadline_s_) {
    wake_up_deadline_s_.reset();
    measuring_ = true;  // nobody answered the WakeUp: the device starts measuring
  }
  while (!pending_.empty() && pending_.front().due_s <= now_s) {
    Pending p = std::move(pending_.front());
    pending_.pop_front();
    out.insert(out.end(), p.bytes.begin(), p.bytes.end());
    switch (p.after) {
      case After::Nothing: break;
      case After::StartMeasuring: measuring_ = true; break;
      case After::StopMeasuring: measuring_ = false; break;
      case After::PowerUp:
        // Restarts at the baud set before (the ack above still left at the old one).
        if (baud_after_reset_) baud_ = *baud_after_reset_;
        baud_after_reset_.reset();
        power_up(p.due_s + options_.reset_s);
        break;
    }
  }
}

std::optional<double> MtiDevice::next_due_s() const {
  std::optional<double> due;
  if (!pending_.empty()) due = pending_.front().due_s;
  if (wake_up_deadline_s_) due = due ? std::min(*due, *wake_up_deadline_s_) : *wake_up_deadline_s_;
  return due;
}

}  // namespace tumble::sim
