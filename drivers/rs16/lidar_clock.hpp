// Maps a free-running sensor clock to the host clock from packet arrival
// times (docs/sensors.md, "Time"): arrival minus the packet's own duration is
// the latest the first firing can have been, so the lower envelope of
// (arrival - duration - sensor time) over time is offset + drift, and whatever
// lies above it is transmission and scheduling jitter. Works with arrival
// times from pcap records or from live sockets alike.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace tumble::rs16 {

struct ClockMapperConfig {
  double window_s = 1.0;         // one envelope point (minimum offset) per window
  std::size_t windows = 8;       // envelope points the offset + drift line is fitted to (2..32)
  double reset_threshold_s = 0.5;  // an offset change this large means the sensor clock jumped
};

class LidarClockMapper {
 public:
  static constexpr std::size_t kMaxWindows = 32;

  // Throws std::invalid_argument naming the field when config is out of range.
  explicit LidarClockMapper(const ClockMapperConfig& config = {});

  // One packet: sensor_t_s = its first firing on the sensor clock, arrival_s =
  // when it reached the host, duration_s = first firing to departure. Returns
  // the host time of sensor_t_s.
  double observe(double sensor_t_s, double arrival_s, double duration_s);
  double to_host(double sensor_t_s) const;

  bool started() const { return started_; }
  std::size_t envelope_points() const { return window_count_; }
  double offset_s() const { return intercept_s_ + drift_ * last_rel_s_; }  // host - sensor at the latest packet
  double drift() const { return drift_; }                                  // d(offset)/d(sensor time)
  double jitter_s() const { return jitter_s_; }  // mean delay above the envelope in the last full window
  std::uint64_t resets() const { return resets_; }

 private:
  struct EnvelopePoint {
    double rel_s;  // sensor time since reference_s_
    double offset_s;
  };
  void start(double sensor_t_s, double offset_s);
  void close_window();
  void fit_line();

  ClockMapperConfig config_;
  bool started_ = false;
  double reference_s_ = 0.0;
  double intercept_s_ = 0.0;
  double drift_ = 0.0;
  double last_rel_s_ = 0.0;
  std::array<EnvelopePoint, kMaxWindows> windows_{};
  std::size_t window_count_ = 0;
  std::size_t window_next_ = 0;
  double window_start_rel_s_ = 0.0;
  EnvelopePoint window_min_{};
  double window_residual_sum_s_ = 0.0;
  std::size_t window_samples_ = 0;
  double jitter_s_ = 0.0;
  std::uint64_t resets_ = 0;
};

}  // namespace tumble::rs16
