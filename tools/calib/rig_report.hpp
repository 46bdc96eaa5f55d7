// What `tumble-calib rig` prints: per pass one line, then the imu: lines for
// tumbled.yaml (pasted as they are) with the uncertainties as comments.
#pragma once

#include <Eigen/Core>
#include <cstdio>

#include "tools/calib/rig_calibration.hpp"

namespace tumble::calib {

// roll, pitch, yaw (degrees) with R = Rz(yaw) Ry(pitch) Rx(roll), tumbled.yaml's convention.
Eigen::Vector3d rpy_deg_of(const Eigen::Matrix3d& R);

void print_rig_pass(std::FILE* out, const RigPass& pass);
void print_rig_calibration(std::FILE* out, const RigCalibration& c);

}  // namespace tumble::calib
