// Maps sensor time (SampleTimeFine) to host time with an online offset and
// drift estimate. Arrival times carry serial and scheduling delays that are
// never negative, so the mapping follows the lower envelope of
// (arrival - sensor time): one minimum per bucket of sensor time, a
// least-squares slope (drift) through the minima of a sliding window, and the
// line shifted down until no observation lies below it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace tumble::mti {

struct TimeMapperOptions {
  double bucket_s = 1.0;           // one envelope point per bucket of sensor time
  std::size_t window_buckets = 64; // drift is fitted over about a minute
  // Below this span the jitter hides the drift (0.1 ms over 10 s = 10 ppm): assume none.
  double min_drift_span_s = 10.0;
  // Crystals are within ~100 ppm (the MTi within 10): a steeper fit is a bad window.
  double max_abs_drift = 500e-6;
  double jitter_smoothing = 0.01;  // weight of a new residual in the jitter average
};

class TimeMapper {
 public:
  explicit TimeMapper(TimeMapperOptions options = {});

  // One observation: a sample's sensor time and the host time its frame
  // started to arrive (transmission time already taken off). Sensor times
  // must not go back: reset() after the sensor clock restarts.
  void observe(double sensor_s, double host_s);
  bool ready() const { return started_; }
  // Host time of a sensor time, on the current envelope. Needs ready().
  double host_time(double sensor_s) const;
  // host - sensor on the envelope at the latest observation.
  double offset_s() const;
  // Rate of change of (host - sensor) per sensor second (1e-6 = 1 ppm).
  double drift() const { return slope_; }
  // Mean height of observations above the envelope.
  double jitter_s() const { return jitter_s_; }
  void reset();

 private:
  struct Bucket {
    std::int64_t index = 0;
    double x = 0;  // sensor time since the first observation
    double y = 0;  // (host - first host) - x: the offset relative to the first one
  };
  void close_bucket();
  void fit();

  TimeMapperOptions options_;
  bool started_ = false;
  double sensor0_s_ = 0;
  double host0_s_ = 0;
  double last_x_ = 0;
  std::vector<Bucket> closed_;  // ring of closed buckets, capacity window_buckets
  std::size_t closed_head_ = 0; // oldest entry once full
  Bucket current_;
  double slope_ = 0;
  double intercept_ = 0;  // envelope y at x = 0
  double jitter_s_ = 0;
};

}  // namespace tumble::mti
