// The RS-16's UDP traffic in arrival order: MSOP packets every 1.332 ms and a
// DIFOP about once a second, each stamped with when the host would receive it
// (the packet leaves after its last firing, then crosses the network).
#pragma once

#include <array>
#include <cstdint>

#include "drivers/rs16/difop_encode.hpp"
#include "tools/sim/lidar_model.hpp"

namespace tumble::sim {

struct LidarLinkConfig {
  std::uint16_t msop_port = 6699;
  std::uint16_t difop_port = 7788;
  double network_latency_s = 0.0003;  // fixed part, after the packet's last firing
  double network_jitter_s = 0.0002;   // mean of an exponential extra delay
  double difop_period_s = 1.0;
};

struct LidarDatagram {
  std::int64_t arrival_ns = 0;  // run time (t = 0 at the run's start)
  std::uint16_t dst_port = 0;
  bool is_difop = false;
  std::array<std::uint8_t, 1248> payload{};
};

// Clock and phase choices of one run, drawn from its seed unless set.
struct LidarTiming {
  std::int64_t epoch_ns = 0;          // UTC of run time 0 (the lidar clock is synced)
  std::int64_t first_packet_ns = 0;   // first firing of the first MSOP (>= 0)
  std::int64_t first_difop_ns = 0;    // when the first DIFOP leaves
  double azimuth_at_zero_deg = 0.0;
};

class LidarStream {
 public:
  LidarStream(const LidarConfig& lidar, const LidarUnit& unit, const LidarLinkConfig& link, const LidarTiming& timing,
              const Scene& scene, const Motion& motion, std::uint64_t noise_seed, double duration_s,
              const People* people = nullptr);

  // The next datagram by arrival time; false after the last one of the run.
  bool next(LidarDatagram& out);

  std::uint64_t msop_count() const { return msop_sent_; }
  std::uint64_t difop_count() const { return difop_sent_; }

 private:
  void prepare_msop();
  void prepare_difop();

  LidarConfig lidar_;
  LidarUnit unit_;
  LidarLinkConfig link_;
  LidarTiming timing_;
  LidarModel model_;
  SensorRng latency_rng_;
  std::int64_t duration_ns_;
  std::int64_t next_packet_ns_;
  std::int64_t next_difop_ns_;
  std::int64_t last_arrival_ns_ = 0;
  std::uint64_t msop_sent_ = 0;
  std::uint64_t difop_sent_ = 0;
  // Staged next datagram of each kind (arrival computed, payload encoded).
  LidarDatagram msop_;
  LidarDatagram difop_;
  bool have_msop_ = false;
  bool have_difop_ = false;
  rs16::MsopPacketData packet_data_;
};

}  // namespace tumble::sim
