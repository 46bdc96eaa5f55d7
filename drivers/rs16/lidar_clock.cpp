#include "drivers/rs16/lidar_clock.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tumble::rs16 {

LidarClockMapper::LidarClockMapper(const ClockMapperConfig& config) : config_(config) {
  if (!(config.window_s > 0.0) || !std::isfinite(config.window_s))
    throw std::invalid_argument("lidar clock: window_s must be > 0 s, got " + std::to_string(config.window_s));
  if (config.windows < 2 || config.windows > kMaxWindows)
    throw std::invalid_argument("lidar clock: windows must be in 2.." + std::to_string(kMaxWindows) + ", got " +
                                std::to_string(config.windows));
  if (!(config.reset_threshold_s > 0.0) || !std::isfinite(config.reset_threshold_s))
    throw std::invalid_argument("lidar clock: reset_threshold_s must be > 0 s, got " +
                                std::to_string(config.reset_threshold_s));
}

void LidarClockMapper::start(double rel_s, double offset_s) {
  intercept_s_ = offset_s;
  drift_ = 0.0;
  last_rel_s_ = rel_s;
  window_count_ = 0;
  window_next_ = 0;
  window_start_rel_s_ = rel_s;
  window_min_ = {rel_s, offset_s};
  window_residual_sum_s_ = 0.0;
  window_samples_ = 0;
}

double LidarClockMapper::observe(double sensor_t_s, double arrival_s, double duration_s) {
  const double offset_s = (arrival_s - duration_s) - sensor_t_s;
  if (!started_) {
    started_ = true;
    reference_s_ = sensor_t_s;
    start(0.0, offset_s);
  }
  const double rel_s = sensor_t_s - reference_s_;
  double predicted_s = intercept_s_ + drift_ * rel_s;
  // Nothing arrives before it was sent: an offset far below the line, or the
  // sensor clock running back, means the sensor (or host) clock was set anew.
  if (offset_s < predicted_s - config_.reset_threshold_s || rel_s < window_start_rel_s_ - config_.reset_threshold_s) {
    ++resets_;
    start(rel_s, offset_s);
    predicted_s = offset_s;
  }
  if (offset_s < predicted_s) {
    intercept_s_ += offset_s - predicted_s;
    predicted_s = offset_s;
  }
  if (window_samples_ == 0 || offset_s < window_min_.offset_s) window_min_ = {rel_s, offset_s};
  window_residual_sum_s_ += offset_s - predicted_s;
  ++window_samples_;
  last_rel_s_ = rel_s;
  if (rel_s - window_start_rel_s_ >= config_.window_s) close_window();
  return sensor_t_s + intercept_s_ + drift_ * rel_s;
}

double LidarClockMapper::to_host(double sensor_t_s) const {
  return sensor_t_s + intercept_s_ + drift_ * (sensor_t_s - reference_s_);
}

void LidarClockMapper::close_window() {
  jitter_s_ = window_residual_sum_s_ / static_cast<double>(window_samples_);
  const double floor_above_line_s = window_min_.offset_s - (intercept_s_ + drift_ * window_min_.rel_s);
  if (floor_above_line_s > config_.reset_threshold_s) {
    // Even the fastest packet of a whole window came much later than the line
    // says: the offset stepped up, so the old envelope no longer holds.
    ++resets_;
    const EnvelopePoint floor = window_min_;
    start(last_rel_s_, floor.offset_s);
    windows_[0] = floor;
    window_count_ = window_next_ = 1;
    return;
  }
  windows_[window_next_] = window_min_;
  window_next_ = (window_next_ + 1) % config_.windows;
  window_count_ = std::min(window_count_ + 1, config_.windows);
  fit_line();
  window_start_rel_s_ = last_rel_s_;
  window_samples_ = 0;
  window_residual_sum_s_ = 0.0;
}

void LidarClockMapper::fit_line() {
  const auto n = static_cast<double>(window_count_);
  double mean_t = 0.0, mean_o = 0.0;
  for (std::size_t i = 0; i < window_count_; ++i) {
    mean_t += windows_[i].rel_s / n;
    mean_o += windows_[i].offset_s / n;
  }
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < window_count_; ++i) {
    sxx += (windows_[i].rel_s - mean_t) * (windows_[i].rel_s - mean_t);
    sxy += (windows_[i].rel_s - mean_t) * (windows_[i].offset_s - mean_o);
  }
  // One point (or points at one instant) carries no drift: keep the last estimate.
  if (sxx > 0.0) drift_ = sxy / sxx;
  intercept_s_ = mean_o - drift_ * mean_t;
}

}  // namespace tumble::rs16
