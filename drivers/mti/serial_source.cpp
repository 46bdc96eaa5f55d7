#include "drivers/mti/serial_source.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/write.hpp>
#include <chrono>

#include "drivers/mti/device_error.hpp"
#include "drivers/mti/message_ids.hpp"

namespace tumble::mti {
namespace {

MtiStreamOptions stream_options(const SerialSourceOptions& o) {
  MtiStreamOptions s;
  s.imu_rate_hz = o.configurator.imu_rate_hz;
  s.baud = o.configurator.baud;
  s.imu_time_offset_s = o.imu_time_offset_s;
  s.time_mapper = o.time_mapper;
  return s;
}

double steady_now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::int64_t realtime_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::chrono::steady_clock::duration from_seconds(double s) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(s));
}

}  // namespace

SerialSource::SerialSource(boost::asio::io_context& io, SerialSourceOptions options, SampleHandler on_sample)
    : options_(std::move(options)),
      on_sample_(std::move(on_sample)),
      port_(io),
      reconnect_timer_(io),
      tick_timer_(io),
      configurator_(options_.configurator),
      stream_(stream_options(options_)),
      backoff_s_(options_.reconnect_min_s) {
  stream_.set_control_handler([this](const XbusFrame& frame) { handle_control_frame(frame); });
}

SerialSource::~SerialSource() {
  stop();
  alive_.reset();
}

void SerialSource::start() {
  if (running_) return;
  running_ = true;
  open();
}

void SerialSource::stop() {
  running_ = false;
  reconnect_timer_.cancel();
  tick_timer_.cancel();
  ticking_ = false;
  boost::system::error_code ignored;
  port_.close(ignored);
  connected_ = false;
}

void SerialSource::open() {
  if (!running_) return;
  const std::uint32_t baud = options_.configurator.baud;
  boost::system::error_code ec;
  port_.open(options_.device, ec);
  if (!ec) port_.set_option(boost::asio::serial_port::baud_rate(baud), ec);
  if (!ec) port_.set_option(boost::asio::serial_port::character_size(8), ec);
  if (!ec) port_.set_option(boost::asio::serial_port::parity(boost::asio::serial_port::parity::none), ec);
  if (!ec) port_.set_option(boost::asio::serial_port::stop_bits(boost::asio::serial_port::stop_bits::one), ec);
  if (!ec)
    port_.set_option(boost::asio::serial_port::flow_control(boost::asio::serial_port::flow_control::none), ec);
  if (ec) {
    boost::system::error_code ignored;
    port_.close(ignored);
    ++failed_opens_;
    ++failed_opens_in_a_row_;
    last_error_ = "cannot open " + options_.device + ": " + ec.message();
    // Said once, then every tenth try: an unplugged device is retried each second.
    spdlog::log(failed_opens_in_a_row_ % 10 == 1 ? spdlog::level::warn : spdlog::level::debug,
                "mti: {}; retrying in {:.2f} s ({} tries)", last_error_, backoff_s_, failed_opens_in_a_row_);
    schedule_reconnect();
    return;
  }
  connected_ = true;
  ++connects_;
  failed_opens_in_a_row_ = 0;
  spdlog::info("mti: connected to {} at {} baud 8N1 ({})", options_.device, baud,
               options_.configurator.configure ? "configuring" : "read-only");
  stream_.restart();
  stream_.set_baud(baud);
  configurator_.start(steady_now_s());
  stream_measuring_ = configurator_.measuring();
  stream_.set_measuring(stream_measuring_);
  read();
  service_configurator();
}

void SerialSource::schedule_reconnect() {
  if (!running_) return;
  reconnect_timer_.expires_after(from_seconds(backoff_s_));
  backoff_s_ = std::min(2 * backoff_s_, options_.reconnect_max_s);
  std::weak_ptr<bool> alive = alive_;
  reconnect_timer_.async_wait([this, alive](const boost::system::error_code& ec) {
    if (ec || alive.expired()) return;
    open();
  });
}

void SerialSource::close_port(const std::string& why) {
  if (!connected_) return;
  connected_ = false;
  ++disconnects_;
  last_error_ = why;
  boost::system::error_code ignored;
  port_.close(ignored);
  tick_timer_.cancel();
  ticking_ = false;
  writing_.clear();
  pending_.clear();
  spdlog::warn("mti: disconnected from {}: {}; reconnecting in {:.2f} s", options_.device, why, backoff_s_);
  schedule_reconnect();
}

void SerialSource::read() {
  std::weak_ptr<bool> alive = alive_;
  port_.async_read_some(boost::asio::buffer(read_buffer_),
                        [this, alive](const boost::system::error_code& ec, std::size_t n) {
                          if (alive.expired() || ec == boost::asio::error::operation_aborted) return;
                          if (ec) {
                            close_port(ec.message());
                            return;
                          }
                          handle_read(n);
                          if (connected_) read();
                        });
}

void SerialSource::handle_read(std::size_t n) {
  const std::int64_t arrival_ns = realtime_now_ns();
  const std::span<const std::uint8_t> bytes(read_buffer_.data(), n);
  samples_.clear();
  stream_.feed(bytes, static_cast<double>(arrival_ns) * 1e-9, samples_);
  if (!samples_.empty()) backoff_s_ = options_.reconnect_min_s;  // a working link: start back-off afresh
  for (const ImuSample& s : samples_) on_sample_(s);
  if (on_read_) on_read_(arrival_ns, bytes);
  service_configurator();
}

void SerialSource::handle_control_frame(const XbusFrame& frame) {
  if (frame.mid == mid::kError && configurator_.measuring())
    spdlog::warn("mti: {} reports {}", options_.device, describe_error(frame.payload));
  configurator_.on_frame(frame, steady_now_s());
  const bool measuring = configurator_.measuring();
  if (measuring == stream_measuring_) return;
  // Switched here, not after the read: MTData2 behind the ack in this read counts.
  stream_measuring_ = measuring;
  const bool started = configurator_.take_measurement_started();
  stream_.set_measuring(measuring, started);
  if (started) {
    const DeviceInfo& d = configurator_.device();
    spdlog::info("mti: {} (id {:08X}, firmware {}) measuring at {} Hz, gyro range {}", d.product_code,
                 d.device_id.value_or(0), d.firmware, options_.configurator.imu_rate_hz,
                 d.ranges.gyro_rad_s ? std::to_string(*d.ranges.gyro_rad_s) + " rad/s" : "unknown");
    if (!d.ranges.gyro_rad_s)
      spdlog::warn("mti: product code '{}' names no gyro range this driver knows (an MTi-30 answers e.g. "
                   "MTi-30-2A8G4): is this the device you meant? Clipping is still taken from its StatusWord",
                   d.product_code);
  }
}

void SerialSource::tick() {
  std::weak_ptr<bool> alive = alive_;
  ticking_ = true;
  tick_timer_.expires_after(from_seconds(options_.tick_s));
  tick_timer_.async_wait([this, alive](const boost::system::error_code& ec) {
    if (ec || alive.expired()) return;
    ticking_ = false;
    if (!connected_) return;
    configurator_.on_tick(steady_now_s());
    service_configurator();
  });
}

// Applies what the configurator decided: a new port baud, bytes to send, a
// failure; keeps ticking while it configures.
void SerialSource::service_configurator() {
  if (!connected_) return;
  if (const auto baud = configurator_.take_baud_switch()) {
    boost::system::error_code ec;
    port_.set_option(boost::asio::serial_port::baud_rate(*baud), ec);
    if (ec) {
      close_port("cannot switch to " + std::to_string(*baud) + " baud: " + ec.message());
      return;
    }
    stream_.set_baud(*baud);
    spdlog::info("mti: {} now at {} baud", options_.device, *baud);
  }
  std::vector<std::uint8_t> out = configurator_.take_output();
  pending_.insert(pending_.end(), out.begin(), out.end());
  write_pending();
  if (configurator_.failed()) {
    spdlog::error("mti: configuring {} failed: {}", options_.device, configurator_.error());
    close_port("configuration failed: " + configurator_.error());
    return;
  }
  const bool configuring = !configurator_.measuring();
  if (configuring && !ticking_) tick();
}

void SerialSource::write_pending() {
  if (!writing_.empty() || pending_.empty() || !connected_) return;
  writing_.swap(pending_);
  std::weak_ptr<bool> alive = alive_;
  boost::asio::async_write(port_, boost::asio::buffer(writing_),
                           [this, alive](const boost::system::error_code& ec, std::size_t) {
                             if (alive.expired() || ec == boost::asio::error::operation_aborted) return;
                             writing_.clear();
                             if (ec) {
                               close_port("write failed: " + ec.message());
                               return;
                             }
                             write_pending();
                           });
}

}  // namespace tumble::mti
