// A fake MTi on the master side of a pseudo-terminal, for the serial source
// tests: it answers configuration commands like a device and streams MTData2.
#pragma once

#include <fcntl.h>
#include <stdlib.h>
#include <unistd.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

#include "drivers/mti/commands.hpp"
#include "drivers/mti/frame_reader.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_encode.hpp"

namespace tumble::mti::test_util {

class PtyDevice {
 public:
  explicit PtyDevice(boost::asio::io_context& io) : master_(io) {
    const int fd = ::posix_openpt(O_RDWR | O_NOCTTY);
    if (fd < 0 || ::grantpt(fd) != 0 || ::unlockpt(fd) != 0) throw std::runtime_error("no pseudo-terminal");
    slave_path_ = ::ptsname(fd);
    master_.assign(fd);
    read();
  }
  ~PtyDevice() { close(); }

  const std::string& slave_path() const { return slave_path_; }
  // The device goes away (unplugged): the port sees EOF/EIO.
  void close() {
    boost::system::error_code ignored;
    master_.close(ignored);
  }
  // Answer configuration commands (else it stays silent, like a device in
  // read-only use that nobody configures).
  void answer_commands(bool on) { answer_ = on; }
  void write(const std::vector<std::uint8_t>& bytes) {
    if (::write(master_.native_handle(), bytes.data(), bytes.size()) != static_cast<ssize_t>(bytes.size()))
      throw std::runtime_error("pty write failed");
  }
  void stream(int first_counter, int n) {
    std::vector<std::uint8_t> bytes;
    for (int i = first_counter; i < first_counter + n; ++i) {
      MtData2Out m;
      m.packet_counter = static_cast<std::uint16_t>(i);
      m.sample_time_fine = static_cast<std::uint32_t>(10'000 + 100 * i);
      m.accel_m_s2 = Eigen::Vector3d(0, 0, 9.81);
      m.gyro_rad_s = Eigen::Vector3d(0.001 * i, 0, 0);
      const auto frame = encode_xbus_frame(mid::kMtData2, encode_mtdata2(m));
      bytes.insert(bytes.end(), frame.begin(), frame.end());
    }
    write(bytes);
  }
  std::size_t bytes_received() const { return bytes_received_; }
  const std::vector<std::uint8_t>& commands() const { return commands_; }
  bool measuring() const { return measuring_; }

 private:
  void read() {
    master_.async_read_some(boost::asio::buffer(buffer_), [this](const boost::system::error_code& ec, std::size_t n) {
      if (ec) return;
      bytes_received_ += n;
      reader_.push(std::span<const std::uint8_t>(buffer_.data(), n));
      while (const auto f = reader_.next()) handle(f->mid, {f->payload.begin(), f->payload.end()});
      read();
    });
  }

  void handle(std::uint8_t mid, const std::vector<std::uint8_t>& payload) {
    commands_.push_back(mid);
    if (!answer_) return;
    switch (mid) {
      case mid::kGoToConfig: reply(mid::kGoToConfigAck, {}); break;
      case mid::kReqDeviceId: reply(mid::kDeviceId, {0x03, 0x70, 0x01, 0x23}); break;
      case mid::kReqProductCode: reply(mid::kProductCode, {'M', 'T', 'i', '-', '3', '0', '-', '2', 'A', '8', 'G', '4'}); break;
      case mid::kReqFirmwareRev: reply(mid::kFirmwareRev, {1, 8, 2}); break;
      case mid::kSetOutputConfiguration: reply(mid::kOutputConfiguration, payload); break;
      case mid::kGoToMeasurement:
        reply(mid::kGoToMeasurementAck, {});
        measuring_ = true;
        break;
      default: break;
    }
  }

  void reply(std::uint8_t mid, const std::vector<std::uint8_t>& payload) { write(encode_xbus_frame(mid, payload)); }

  boost::asio::posix::stream_descriptor master_;
  std::string slave_path_;
  std::array<std::uint8_t, 1024> buffer_{};
  FrameReader reader_;
  bool answer_ = true;
  bool measuring_ = false;
  std::size_t bytes_received_ = 0;
  std::vector<std::uint8_t> commands_;
};

// Runs io in 10 ms slices until done() or the limit: no sleeping on the clock.
template <class Done>
bool run_until(boost::asio::io_context& io, Done done, std::chrono::milliseconds limit = std::chrono::seconds(10)) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!done() && std::chrono::steady_clock::now() < end) {
    io.restart();
    io.run_for(std::chrono::milliseconds(10));
  }
  return done();
}

}  // namespace tumble::mti::test_util
