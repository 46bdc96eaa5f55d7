// The simulator's ground truth (ground_truth.tum: "t x y z qx qy qz qw", the
// lidar pose T_WL in the scene frame, host-clock seconds, ≥ 1 kHz): the exact
// trajectory that builds the reference map, places each de-skewed scan and
// gives each scan its true speed. Poses between samples: linear in position,
// slerp in rotation (at 1 kHz the error is far below a micrometre).
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <filesystem>
#include <vector>

namespace tumble::calib {

class GroundTruth {
 public:
  // Throws InputError "file:line: why" (too few poses, bad numbers, a
  // non-unit quaternion, time not increasing).
  static GroundTruth load(const std::filesystem::path& path);
  GroundTruth(std::vector<double> times_s, std::vector<Eigen::Vector3d> positions,
              std::vector<Eigen::Quaterniond> rotations);

  double t_begin_s() const { return times_s_.front(); }
  double t_end_s() const { return times_s_.back(); }
  bool covers(double t0_s, double t1_s) const { return t0_s >= t_begin_s() && t1_s <= t_end_s(); }

  // T_WL(t), clamped to the ends. `hint`: pass the same variable for
  // successive queries at nearly increasing times (O(1) each).
  Eigen::Isometry3d pose_at(double t_s, std::size_t& hint) const;
  Eigen::Isometry3d pose_at(double t_s) const;

  // Mean speed over [t0, t1] from the chord: |p(t1) − p(t0)| / (t1 − t0),
  // and the rotation angle between the two poses / (t1 − t0). A scan lasts
  // 0.1 s, far less than a turntable revolution, so the chord is the mean.
  double mean_linear_speed_m_s(double t0_s, double t1_s) const;
  double mean_angular_rate_rad_s(double t0_s, double t1_s) const;
  // The first time the lidar is 1 mm or 1 mrad away from its first pose
  // (t_end_s() when it never is).
  double motion_start_s() const;
  // Unit direction from the first position to the farthest one (the rail's
  // axis); zero when the lidar did not move.
  Eigen::Vector3d travel_direction() const;

 private:
  std::size_t segment(double t_s, std::size_t& hint) const;

  std::vector<double> times_s_;
  std::vector<Eigen::Vector3d> positions_;
  std::vector<Eigen::Quaterniond> rotations_;
};

}  // namespace tumble::calib
