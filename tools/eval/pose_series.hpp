// A trajectory as timed poses (ground truth or an estimate), and the two
// questions the metrics ask of it: the pose at any time inside it, and the
// length of the path between two times.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <vector>

namespace tumble::eval {

struct TimedPose {
  double t_s = 0.0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // unit, W <- L
};

// Times strictly increasing.
using PoseSeries = std::vector<TimedPose>;

Eigen::Isometry3d to_isometry(const TimedPose& pose);

// Linear in position, slerp in orientation between the two samples around t.
// Throws std::out_of_range when t is outside [front, back].
Eigen::Isometry3d pose_at(const PoseSeries& series, double t_s);

// The series' own sample at t_s, or none. A scan's estimated pose is looked up
// this way: the trajectory file and the scan log both print the scan's start,
// to within 0.1 ms.
std::optional<TimedPose> sample_at(const PoseSeries& series, double t_s);

// Sum of sample-to-sample distances between t0 and t1 (ends interpolated),
// t0 <= t1, both inside the series. On a 1 kHz ground truth this is the
// distance travelled to well under a millimetre per metre.
double path_length_m(const PoseSeries& series, double t0_s, double t1_s);

// Rotation angle of a rotation, in degrees, accurate near zero.
double rotation_angle_deg(const Eigen::Matrix3d& rotation);

}  // namespace tumble::eval
