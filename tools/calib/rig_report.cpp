#include "tools/calib/rig_report.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tumble::calib {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

// Prints -0.0 as 0.
double tidy(double v, double resolution) {
  const double r = std::round(v / resolution) * resolution;
  return r == 0.0 ? 0.0 : r;
}

}  // namespace

Eigen::Vector3d rpy_deg_of(const Eigen::Matrix3d& R) {
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double roll = std::atan2(R(2, 1), R(2, 2)), yaw = std::atan2(R(1, 0), R(0, 0));
  return Eigen::Vector3d(roll, pitch, yaw) * kDeg;
}

void print_rig_pass(std::FILE* out, const RigPass& p) {
  const Eigen::Vector3d rpy = rpy_deg_of(p.rotation.R_li);
  std::fprintf(out,
               "%s: %zu scans, %zu registered, %zu scan-to-scan rotations (%zu used); offset %.4f ms, rotation rpy "
               "[%.3f, %.3f, %.3f] deg, residual %.4f deg RMS\n",
               p.name.c_str(), p.scans, p.scans_registered, p.increments, p.rotation.used, p.offset.offset_s * 1e3,
               rpy.x(), rpy.y(), rpy.z(), p.rotation.rms_residual_rad * kDeg);
}

void print_rig_calibration(std::FILE* out, const RigCalibration& c) {
  const Eigen::Vector3d rpy = rpy_deg_of(c.rotation.R_li);
  const LeverArmEstimate& arm = c.lever_arm;
  const Eigen::Vector3d b = c.rotation.gyro_bias_rad_s * kDeg;
  std::fprintf(out, "\nIMU samples: %zu; pass 1 followed the gyro for %.1f s (least-turned axis %.2f deg per scan)\n",
               c.imu_samples, c.bootstrap_s, c.bootstrap_weakest_axis_deg);
  std::fprintf(out, "gyro bias (IMU frame): [%.4f, %.4f, %.4f] deg/s\n", b.x(), b.y(), b.z());
  if (arm.solved) {
    const Eigen::Vector3d ba = arm.accel_bias_m_s2;
    std::fprintf(out,
                 "lever arm: %zu windows, residual %.4f m/s RMS, gravity fitted %.3f m/s^2, accelerometer bias "
                 "[%.3f, %.3f, %.3f] m/s^2\n",
                 arm.windows, arm.rms_residual_m_s, arm.gravity_m_s2, ba.x(), ba.y(), ba.z());
  } else {
    std::fprintf(out, "lever arm: not solved (%zu windows of registered scans)\n", arm.windows);
  }

  std::fprintf(out, "\n# for tumbled.yaml (tumble-calib rig):\nimu:\n");
  std::fprintf(out, "  imu_time_offset_s: %.6f  # 1 sigma %.6f s\n", tidy(c.offset.offset_s, 1e-6), c.offset.sigma_s);
  std::fprintf(out, "  extrinsic_T_LI:\n");
  if (c.lever_arm_observable) {
    std::fprintf(out, "    translation_m: [%.4f, %.4f, %.4f]  # 1 sigma [%.4f, %.4f, %.4f] m\n", tidy(arm.t_m.x(), 1e-4),
                 tidy(arm.t_m.y(), 1e-4), tidy(arm.t_m.z(), 1e-4), arm.sigma_m.x(), arm.sigma_m.y(), arm.sigma_m.z());
  } else if (arm.solved) {
    std::fprintf(out,
                 "    translation_m: [0, 0, 0]  # NOT OBSERVABLE: fitted [%.4f, %.4f, %.4f] +- [%.4f, %.4f, %.4f] m "
                 "(1 sigma), gravity %.3f m/s^2; measure it on the mount\n",
                 arm.t_m.x(), arm.t_m.y(), arm.t_m.z(), arm.sigma_m.x(), arm.sigma_m.y(), arm.sigma_m.z(),
                 arm.gravity_m_s2);
  } else {
    std::fprintf(out, "    translation_m: [0, 0, 0]  # NOT OBSERVABLE from this recording; measure it on the mount\n");
  }
  std::fprintf(out, "    rotation_rpy_deg: [%.3f, %.3f, %.3f]  # 1 sigma %.3f deg\n", tidy(rpy.x(), 1e-3),
               tidy(rpy.y(), 1e-3), tidy(rpy.z(), 1e-3), c.rotation.sigma_deg);
}

}  // namespace tumble::calib
