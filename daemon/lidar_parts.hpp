// The RS-16 behind the daemon's lidar seams: live UDP sockets, and the
// decoder that turns MSOP datagrams into point blocks on the io thread.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "daemon/config.hpp"
#include "daemon/datagram_rate.hpp"
#include "daemon/lidar_identity.hpp"
#include "daemon/rate_limited_log.hpp"
#include "daemon/seams.hpp"
#include "drivers/rs16/decoder.hpp"
#include "drivers/rs16/decoder_stats.hpp"
#include "drivers/rs16/lidar_datagram.hpp"
#include "drivers/rs16/udp_source.hpp"

namespace tumble::daemon {

// Both lidar ports, any sender: the decoder keeps to the lidar
// (lidar_identity.hpp) so that foreign datagrams are counted and reported in
// one place.
//
// A port still held by another process (a previous tumbled that has not yet
// exited) or an address not yet assigned (DHCP, a link coming up after
// tumbled) is waited out: the bind is retried on the io thread with a
// growing delay until it succeeds or tumbled stops, each failure a warning.
// Meanwhile the lidar is silent to the health machine, as it is.
class LiveLidarSource : public LidarDatagramSource {
 public:
  static constexpr std::chrono::milliseconds kFirstRetryDelay{250};
  static constexpr std::chrono::milliseconds kLongestRetryDelay{8000};

  // Binds the sockets, or schedules the retries when the address is busy or
  // not yet assigned; throws std::runtime_error (naming the address and
  // port) for any other reason.
  LiveLidarSource(boost::asio::io_context& io, const LidarConfig& config);
  void start(std::function<void(const LidarDatagram&)> on_datagram, std::function<void()> on_end) override;
  void stop() override;

 private:
  bool try_bind();
  void retry_later();

  LidarConfig config_;
  rs16::SourceConfig ports_;
  boost::asio::io_context& io_;
  boost::asio::steady_timer retry_timer_;
  std::chrono::milliseconds retry_delay_ = kFirstRetryDelay;
  std::chrono::steady_clock::time_point first_failure_;
  int failed_binds_ = 0;
  bool stopped_ = false;
  std::function<void(const LidarDatagram&)> on_datagram_;
  std::unique_ptr<rs16::UdpSource> udp_;
};

class Rs16LidarDecoder : public LidarDecoder {
 public:
  explicit Rs16LidarDecoder(const LidarConfig& config);
  bool decode(const LidarDatagram& datagram, PointBlock& block) override;
  bool last_from_the_lidar() const override { return last_from_the_lidar_; }
  void report(PipelineCounters& counters) const override;

 private:
  rs16::SourceConfig source_;
  rs16::Decoder decoder_;
  rs16::DecoderStats stats_;
  void ignore(const LidarDatagram& datagram);

  LidarIdentity lidar_;
  bool last_from_the_lidar_ = false;
  DatagramRate foreign_msop_rate_;
  std::int64_t foreign_ = 0;
  std::uint64_t clock_resets_ = 0;
  RateLimitedLog fault_log_;  // foreign datagrams, header clock jumps
};

}  // namespace tumble::daemon
