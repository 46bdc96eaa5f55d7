// The live MTi: a serial port (8N1) on a Boost.Asio io_context. Stamps each
// read with its host arrival time, drives the configurator, decodes samples,
// and reconnects with back-off when the device goes away.
#pragma once

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/serial_port.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "drivers/mti/configurator.hpp"
#include "drivers/mti/mti_stream.hpp"

namespace tumble::mti {

struct SerialSourceOptions {
  std::string device;                // e.g. /dev/ttyUSB0 or a /dev/serial/by-id link
  ConfiguratorOptions configurator;  // baud, read-only or configure, rate, format, baud change
  double imu_time_offset_s = 0.0;
  TimeMapperOptions time_mapper;
  // Back-off doubles from reconnect_min_s up to reconnect_max_s, and resets
  // once samples flow. One open() a second costs nothing, and finds a
  // replugged MTi within a second of its return.
  double reconnect_min_s = 0.1;
  double reconnect_max_s = 1.0;
  double tick_s = 0.02;              // configurator retries and timeouts
};

class SerialSource {
 public:
  using SampleHandler = std::function<void(const ImuSample&)>;
  // Every read as the port delivered it, with its arrival time (for recording),
  // called after the samples decoded from it went to the SampleHandler.
  using ReadHandler = std::function<void(std::int64_t arrival_ns, std::span<const std::uint8_t> bytes)>;

  // Throws std::invalid_argument for options the configurator rejects.
  SerialSource(boost::asio::io_context& io, SerialSourceOptions options, SampleHandler on_sample);
  ~SerialSource();
  SerialSource(const SerialSource&) = delete;
  SerialSource& operator=(const SerialSource&) = delete;

  void set_read_handler(ReadHandler handler) { on_read_ = std::move(handler); }
  void start();
  void stop();

  bool connected() const { return connected_; }
  ConfigStep config_step() const { return configurator_.step(); }
  const DeviceInfo& device() const { return configurator_.device(); }
  const MtiStats& stats() const { return stream_.stats(); }
  const TimeMapper& time_mapper() const { return stream_.time_mapper(); }
  std::uint64_t connects() const { return connects_; }
  std::uint64_t disconnects() const { return disconnects_; }
  std::uint64_t failed_opens() const { return failed_opens_; }
  // The wait before the next reconnect attempt.
  double backoff_s() const { return backoff_s_; }
  // Why the last connection attempt or configuration failed; empty when none did.
  const std::string& last_error() const { return last_error_; }

 private:
  void open();
  void schedule_reconnect();
  void close_port(const std::string& why);
  void read();
  void handle_read(std::size_t n);
  void handle_control_frame(const XbusFrame& frame);
  void tick();
  void service_configurator();
  void write_pending();

  SerialSourceOptions options_;
  SampleHandler on_sample_;
  ReadHandler on_read_;
  boost::asio::serial_port port_;
  boost::asio::steady_timer reconnect_timer_;
  boost::asio::steady_timer tick_timer_;
  Configurator configurator_;
  MtiStream stream_;
  std::array<std::uint8_t, 4096> read_buffer_{};
  std::vector<ImuSample> samples_;
  std::vector<std::uint8_t> writing_;
  std::vector<std::uint8_t> pending_;
  bool running_ = false;
  bool connected_ = false;
  bool ticking_ = false;
  bool stream_measuring_ = false;
  double backoff_s_ = 0;
  std::uint64_t connects_ = 0;
  std::uint64_t disconnects_ = 0;
  std::uint64_t failed_opens_ = 0;
  std::uint64_t failed_opens_in_a_row_ = 0;  // since the last successful open
  std::string last_error_;
  // Completion handlers outlive a destroyed source in the io_context queue;
  // they check this token before touching the source.
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace tumble::mti
