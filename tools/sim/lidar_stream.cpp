#include "tools/sim/lidar_stream.hpp"

#include <algorithm>
#include <cmath>

namespace tumble::sim {
namespace {

// A 1290-byte frame on 100 Mbit/s Ethernet: two frames cannot arrive closer.
constexpr std::int64_t kWireTimeNs = 103'200;

std::int64_t seconds_to_ns(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }

}  // namespace

LidarStream::LidarStream(const LidarConfig& lidar, const LidarUnit& unit, const LidarLinkConfig& link,
                         const LidarTiming& timing, const Scene& scene, const Motion& motion,
                         std::uint64_t noise_seed, double duration_s, const People* people)
    : lidar_(lidar),
      unit_(unit),
      link_(link),
      timing_(timing),
      model_(lidar, unit, scene, motion, noise_seed, timing.azimuth_at_zero_deg, people),
      latency_rng_(noise_seed, "lidar-network"),
      duration_ns_(seconds_to_ns(duration_s)),
      next_packet_ns_(timing.first_packet_ns),
      next_difop_ns_(timing.first_difop_ns) {
  prepare_msop();
  prepare_difop();
}

void LidarStream::prepare_msop() {
  have_msop_ = next_packet_ns_ + kRs16PacketSpanNs <= duration_ns_;
  if (!have_msop_) return;
  packet_data_.utc_time_ns = timing_.epoch_ns + next_packet_ns_;
  model_.fill_packet(next_packet_ns_, packet_data_);
  msop_.payload = rs16::encode_msop(packet_data_);
  msop_.dst_port = link_.msop_port;
  msop_.is_difop = false;
  const double delay_s = link_.network_latency_s - link_.network_jitter_s * std::log(1.0 - latency_rng_.uniform());
  msop_.arrival_ns = next_packet_ns_ + kRs16PacketSpanNs + seconds_to_ns(delay_s);
  next_packet_ns_ += kRs16PacketPeriodNs;
}

void LidarStream::prepare_difop() {
  have_difop_ = next_difop_ns_ < duration_ns_;
  if (!have_difop_) return;
  rs16::DifopData d;
  d.motor_rpm = static_cast<std::uint16_t>(lidar_.rpm);
  d.vertical_angles_deg = unit_.vertical_angles_deg;
  d.return_mode = 1;
  d.utc_time_ns = timing_.epoch_ns + next_difop_ns_;
  d.serial = unit_.serial;
  difop_.payload = rs16::encode_difop(d);
  difop_.dst_port = link_.difop_port;
  difop_.is_difop = true;
  difop_.arrival_ns = next_difop_ns_ + seconds_to_ns(link_.network_latency_s);
  next_difop_ns_ += seconds_to_ns(link_.difop_period_s);
}

bool LidarStream::next(LidarDatagram& out) {
  if (!have_msop_ && !have_difop_) return false;
  const bool take_difop = have_difop_ && (!have_msop_ || difop_.arrival_ns < msop_.arrival_ns);
  out = take_difop ? difop_ : msop_;
  // Frames share one wire: a late one delays the next instead of overtaking it.
  out.arrival_ns = std::max(out.arrival_ns, last_arrival_ns_ + kWireTimeNs);
  last_arrival_ns_ = out.arrival_ns;
  if (take_difop) {
    ++difop_sent_;
    prepare_difop();
  } else {
    ++msop_sent_;
    prepare_msop();
  }
  return true;
}

}  // namespace tumble::sim
