#include "drivers/mti/time_mapper.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tumble::mti {

TimeMapper::TimeMapper(TimeMapperOptions options) : options_(options) {
  if (options_.bucket_s <= 0 || options_.window_buckets < 2)
    throw std::invalid_argument("time mapper: bucket_s must be > 0 and window_buckets >= 2");
  closed_.reserve(options_.window_buckets);
}

void TimeMapper::reset() {
  started_ = false;
  closed_.clear();
  closed_head_ = 0;
  slope_ = intercept_ = jitter_s_ = 0;
}

void TimeMapper::observe(double sensor_s, double host_s) {
  if (!started_) {
    started_ = true;
    sensor0_s_ = sensor_s;
    host0_s_ = host_s;
    last_x_ = 0;
    current_ = {0, 0, 0};
    slope_ = intercept_ = jitter_s_ = 0;
    return;
  }
  const double x = sensor_s - sensor0_s_;
  const double y = (host_s - host0_s_) - x;
  last_x_ = x;
  const auto index = static_cast<std::int64_t>(std::floor(x / options_.bucket_s));
  if (index > current_.index) {
    close_bucket();
    current_ = {index, x, y};
    fit();
  } else if (y < current_.y) {
    current_.x = x;
    current_.y = y;
    intercept_ = std::min(intercept_, y - slope_ * x);
  }
  const double residual = y - (intercept_ + slope_ * x);
  jitter_s_ += options_.jitter_smoothing * (residual - jitter_s_);
}

void TimeMapper::close_bucket() {
  if (closed_.size() < options_.window_buckets) {
    closed_.push_back(current_);
  } else {
    closed_[closed_head_] = current_;
    closed_head_ = (closed_head_ + 1) % closed_.size();
  }
}

void TimeMapper::fit() {
  double x_min = std::numeric_limits<double>::max();
  double x_max = std::numeric_limits<double>::lowest();
  double sx = 0, sy = 0;
  for (const Bucket& b : closed_) {
    x_min = std::min(x_min, b.x);
    x_max = std::max(x_max, b.x);
    sx += b.x;
    sy += b.y;
  }
  slope_ = 0;
  const auto n = static_cast<double>(closed_.size());
  if (closed_.size() >= 2 && x_max - x_min >= options_.min_drift_span_s) {
    const double mx = sx / n, my = sy / n;
    double sxx = 0, sxy = 0;
    for (const Bucket& b : closed_) {
      sxx += (b.x - mx) * (b.x - mx);
      sxy += (b.x - mx) * (b.y - my);
    }
    if (sxx > 0) slope_ = std::clamp(sxy / sxx, -options_.max_abs_drift, options_.max_abs_drift);
  }
  intercept_ = current_.y - slope_ * current_.x;
  for (const Bucket& b : closed_) intercept_ = std::min(intercept_, b.y - slope_ * b.x);
}

double TimeMapper::host_time(double sensor_s) const {
  const double x = sensor_s - sensor0_s_;
  return host0_s_ + x + intercept_ + slope_ * x;
}

double TimeMapper::offset_s() const { return (host0_s_ - sensor0_s_) + intercept_ + slope_ * last_x_; }

}  // namespace tumble::mti
