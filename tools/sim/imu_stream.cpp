#include "tools/sim/imu_stream.hpp"

#include <algorithm>
#include <cmath>

#include "drivers/mti/xbus_frame.hpp"

namespace tumble::sim {
namespace {

constexpr std::uint8_t kMidMtData2 = 0x36;
constexpr std::uint8_t kMidGoToMeasurementAck = 0x11;
constexpr std::size_t kMaxReadBytes = 4095;  // a tty read never returns more than its canonical buffer

std::vector<std::uint8_t> mtdata2_frame(const ImuMeasurement& m, mti::NumberFormat format) {
  mti::MtData2Out out;
  out.packet_counter = m.packet_counter;
  out.sample_time_fine = m.sample_time_fine;
  out.accel_m_s2 = m.accel_m_s2;
  out.gyro_rad_s = m.gyro_rad_s;
  out.status_word = m.status_word;
  return mti::encode_xbus_frame(kMidMtData2, mti::encode_mtdata2(out, format));
}

}  // namespace

std::size_t mtdata2_frame_bytes(mti::NumberFormat format) { return mtdata2_frame(ImuMeasurement{}, format).size(); }

ImuStream::ImuStream(const ImuConfig& imu, const ImuClock& clock, const ImuLinkConfig& link,
                     const Eigen::Isometry3d& T_LI, const Motion& motion, std::uint64_t noise_seed,
                     bool noise_enabled, double duration_s)
    : link_(link),
      model_(imu, clock, T_LI, motion, noise_seed, noise_enabled),
      line_(link.baud),
      read_rng_(noise_seed, "imu-reads"),
      duration_s_(duration_s) {
  if (link_.leading_garbage_bytes > 0) {
    // The tail of the frame that was on the wire when the capture began.
    ImuMeasurement earlier;
    earlier.accel_m_s2 = Eigen::Vector3d(0.0, 0.0, kStandardGravity_m_s2);
    earlier.packet_counter = static_cast<std::uint16_t>(clock.first_packet_counter - 1);
    earlier.sample_time_fine = clock.first_sample_time_fine - static_cast<std::uint32_t>(10'000 / imu.rate_hz);
    const auto frame = mtdata2_frame(earlier, link_.number_format);
    const std::size_t n = std::min(frame.size() - 1, static_cast<std::size_t>(link_.leading_garbage_bytes));
    line_.send(0.0, std::span(frame).last(n));
  }
  if (link_.leading_config_ack) line_.send(0.0, mti::encode_xbus_frame(kMidGoToMeasurementAck, {}));
}

void ImuStream::queue_next_frame() {
  if (!have_pending_ && !samples_done_) {
    have_pending_ = model_.next(duration_s_, pending_);
    samples_done_ = !have_pending_;
  }
  if (!have_pending_) return;
  line_.send(pending_.t_s + link_.processing_latency_s, mtdata2_frame(pending_, link_.number_format));
  ++frames_;
  if (pending_.status_word != 0) ++clipped_;
  have_pending_ = false;
}

void ImuStream::queue_frames_ready_by(double t_s) {
  while (!samples_done_) {
    if (!have_pending_) {
      have_pending_ = model_.next(duration_s_, pending_);
      samples_done_ = !have_pending_;
      if (samples_done_) return;
    }
    if (pending_.t_s + link_.processing_latency_s > t_s) return;
    queue_next_frame();
  }
}

bool ImuStream::next(SerialRead& out) {
  while (!line_.first_unread_arrival_s() && !samples_done_) queue_next_frame();
  const auto first_arrival_s = line_.first_unread_arrival_s();
  if (!first_arrival_s) return false;
  // The reader wakes a little after data arrives; everything that came in by
  // then (possibly several frames, possibly half of one) is one read.
  const double read_s = std::max(*first_arrival_s, last_read_s_) + link_.read_latency_s +
                        link_.read_jitter_s * read_rng_.uniform();
  queue_frames_ready_by(read_s);
  out.bytes.clear();
  line_.read_until(read_s, kMaxReadBytes, out.bytes);
  out.arrival_ns = std::llround(read_s * 1e9);
  last_read_s_ = read_s;
  return true;
}

}  // namespace tumble::sim
