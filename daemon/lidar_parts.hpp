// The RS-16 behind the daemon's lidar seams: live UDP sockets, and the
// decoder that turns MSOP datagrams into point blocks on the io thread.
#pragma once

#include <boost/asio/io_context.hpp>
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
class LiveLidarSource : public LidarDatagramSource {
 public:
  // Binds the sockets; throws std::runtime_error naming the address and port.
  LiveLidarSource(boost::asio::io_context& io, const LidarConfig& config);
  void start(std::function<void(const LidarDatagram&)> on_datagram, std::function<void()> on_end) override;
  void stop() override;

 private:
  rs16::SourceConfig ports_;
  std::function<void(const LidarDatagram&)> on_datagram_;
  std::unique_ptr<rs16::UdpSource> udp_;
};

class Rs16LidarDecoder : public LidarDecoder {
 public:
  explicit Rs16LidarDecoder(const LidarConfig& config);
  bool decode(const LidarDatagram& datagram, PointBlock& block) override;
  void report(PipelineCounters& counters) const override;

 private:
  rs16::SourceConfig source_;
  rs16::Decoder decoder_;
  rs16::DecoderStats stats_;
  void ignore(const LidarDatagram& datagram);

  LidarIdentity lidar_;
  DatagramRate foreign_msop_rate_;
  std::int64_t foreign_ = 0;
  std::uint64_t clock_resets_ = 0;
  RateLimitedLog fault_log_;  // foreign datagrams, header clock jumps
};

}  // namespace tumble::daemon
