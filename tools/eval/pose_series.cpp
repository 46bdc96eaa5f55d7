#include "tools/eval/pose_series.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace tumble::eval {
namespace {

constexpr double kSameTime_s = 1e-4;

// Index of the last sample with t <= t_s; the caller has checked the span.
std::size_t segment_start(const PoseSeries& series, double t_s) {
  const auto after =
      std::upper_bound(series.begin(), series.end(), t_s, [](double t, const TimedPose& pose) { return t < pose.t_s; });
  const auto index = static_cast<std::size_t>(after - series.begin());
  return std::min(index == 0 ? 0 : index - 1, series.size() - 2);
}

Eigen::Vector3d position_at(const PoseSeries& series, std::size_t i, double t_s) {
  const TimedPose& a = series[i];
  const TimedPose& b = series[i + 1];
  const double alpha = (t_s - a.t_s) / (b.t_s - a.t_s);
  return a.position_m + alpha * (b.position_m - a.position_m);
}

void require_inside(const PoseSeries& series, double t_s) {
  if (series.size() < 2 || t_s < series.front().t_s || t_s > series.back().t_s) {
    const std::string span =
        series.empty() ? std::string("an empty series")
                       : "[" + std::to_string(series.front().t_s) + ", " + std::to_string(series.back().t_s) + "]";
    throw std::out_of_range("time " + std::to_string(t_s) + " s is outside " + span);
  }
}

}  // namespace

Eigen::Isometry3d to_isometry(const TimedPose& pose) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = pose.orientation.normalized().toRotationMatrix();
  transform.translation() = pose.position_m;
  return transform;
}

Eigen::Isometry3d pose_at(const PoseSeries& series, double t_s) {
  require_inside(series, t_s);
  const std::size_t i = segment_start(series, t_s);
  const TimedPose& a = series[i];
  const TimedPose& b = series[i + 1];
  const double alpha = (t_s - a.t_s) / (b.t_s - a.t_s);
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = a.orientation.slerp(alpha, b.orientation).normalized().toRotationMatrix();
  transform.translation() = position_at(series, i, t_s);
  return transform;
}

std::optional<TimedPose> sample_at(const PoseSeries& series, double t_s) {
  const auto it = std::lower_bound(series.begin(), series.end(), t_s - kSameTime_s,
                                   [](const TimedPose& p, double t) { return p.t_s < t; });
  if (it == series.end() || std::abs(it->t_s - t_s) > kSameTime_s) return std::nullopt;
  return *it;
}

double path_length_m(const PoseSeries& series, double t0_s, double t1_s) {
  require_inside(series, t0_s);
  require_inside(series, t1_s);
  if (t1_s < t0_s) throw std::invalid_argument("path_length_m: t1 is before t0");
  std::size_t i = segment_start(series, t0_s);
  const std::size_t last = segment_start(series, t1_s);
  Eigen::Vector3d from = position_at(series, i, t0_s);
  double length_m = 0.0;
  for (; i < last; ++i) {
    length_m += (series[i + 1].position_m - from).norm();
    from = series[i + 1].position_m;
  }
  return length_m + (position_at(series, last, t1_s) - from).norm();
}

double rotation_angle_deg(const Eigen::Matrix3d& rotation) {
  const Eigen::Quaterniond q(rotation);
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w())) * 180.0 / std::numbers::pi;
}

}  // namespace tumble::eval
