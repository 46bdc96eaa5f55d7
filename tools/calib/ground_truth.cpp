#include "tools/calib/ground_truth.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "tools/calib/input_error.hpp"

namespace tumble::calib {

GroundTruth GroundTruth::load(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot be opened");
  std::vector<double> times;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Quaterniond> rotations;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string where = path.string() + ":" + std::to_string(line_number) + ": ";
    std::istringstream fields(line);
    double v[8];
    for (double& x : v)
      if (!(fields >> x) || !std::isfinite(x)) throw InputError(where + "expected 8 numbers \"t x y z qx qy qz qw\"");
    std::string extra;
    if (fields >> extra) throw InputError(where + "more than 8 fields");
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw InputError(where + "quaternion is not unit (norm " + std::to_string(q.norm()) + ")");
    if (!times.empty() && !(v[0] > times.back()))
      throw InputError(where + "time " + std::to_string(v[0]) + " does not increase");
    times.push_back(v[0]);
    positions.emplace_back(v[1], v[2], v[3]);
    rotations.push_back(q.normalized());
  }
  if (in.bad()) throw InputError(path.string() + ": read error");
  if (times.size() < 2) throw InputError(path.string() + ": fewer than 2 poses");
  return GroundTruth(std::move(times), std::move(positions), std::move(rotations));
}

GroundTruth::GroundTruth(std::vector<double> times_s, std::vector<Eigen::Vector3d> positions,
                         std::vector<Eigen::Quaterniond> rotations)
    : times_s_(std::move(times_s)), positions_(std::move(positions)), rotations_(std::move(rotations)) {
  if (times_s_.size() < 2 || positions_.size() != times_s_.size() || rotations_.size() != times_s_.size())
    throw std::invalid_argument("GroundTruth needs at least 2 poses and equal-length arrays");
}

std::size_t GroundTruth::segment(double t_s, std::size_t& hint) const {
  const std::size_t last = times_s_.size() - 2;
  if (hint > last) hint = last;
  // Nearly increasing queries: try the hinted segment and its successor first.
  for (std::size_t i = hint; i <= std::min(hint + 1, last); ++i)
    if (times_s_[i] <= t_s && t_s < times_s_[i + 1]) return hint = i;
  const auto it = std::upper_bound(times_s_.begin(), times_s_.end(), t_s);
  const std::size_t upper = static_cast<std::size_t>(it - times_s_.begin());
  hint = std::min(upper == 0 ? 0 : upper - 1, last);
  return hint;
}

Eigen::Isometry3d GroundTruth::pose_at(double t_s, std::size_t& hint) const {
  const std::size_t i = segment(t_s, hint);
  const double a = std::clamp((t_s - times_s_[i]) / (times_s_[i + 1] - times_s_[i]), 0.0, 1.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotations_[i].slerp(a, rotations_[i + 1]).toRotationMatrix();
  T.translation() = (1 - a) * positions_[i] + a * positions_[i + 1];
  return T;
}

Eigen::Isometry3d GroundTruth::pose_at(double t_s) const {
  std::size_t hint = 0;
  return pose_at(t_s, hint);
}

double GroundTruth::mean_linear_speed_m_s(double t0_s, double t1_s) const {
  if (!(t1_s > t0_s)) return 0.0;
  return (pose_at(t1_s).translation() - pose_at(t0_s).translation()).norm() / (t1_s - t0_s);
}

double GroundTruth::mean_angular_rate_rad_s(double t0_s, double t1_s) const {
  if (!(t1_s > t0_s)) return 0.0;
  const Eigen::Matrix3d relative = pose_at(t0_s).linear().transpose() * pose_at(t1_s).linear();
  return Eigen::AngleAxisd(relative).angle() / (t1_s - t0_s);
}

double GroundTruth::motion_start_s() const {
  for (std::size_t i = 1; i < times_s_.size(); ++i)
    if ((positions_[i] - positions_[0]).norm() > 1e-3 || rotations_[i].angularDistance(rotations_[0]) > 1e-3)
      return times_s_[i];
  return t_end_s();
}

Eigen::Vector3d GroundTruth::travel_direction() const {
  // The farthest point from the start, so a run out and back still has an axis.
  Eigen::Vector3d farthest = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : positions_)
    if ((p - positions_.front()).norm() > farthest.norm()) farthest = p - positions_.front();
  return farthest.norm() > 1e-6 ? Eigen::Vector3d(farthest.normalized()) : Eigen::Vector3d::Zero();
}

}  // namespace tumble::calib
