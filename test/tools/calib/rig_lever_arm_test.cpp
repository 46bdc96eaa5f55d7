// The lever arm from exact synthetic kinematics: the simulator's waving
// motion sampled as scan poses (10 Hz) and as an ideal IMU (100 Hz) mounted
// with a known arm, accelerometer bias and rotation; gravity in the map frame
// is the first pose's (the map starts there, tilted).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <vector>

#include "tools/calib/rig_lever_arm.hpp"
#include "tools/sim/imu_model.hpp"
#include "tools/sim/motion_load.hpp"

namespace tumble::calib {
namespace {

struct Recording {
  std::vector<ScanPose> poses;
  std::vector<ImuSample> imu;
};

Recording waving(const Eigen::Isometry3d& T_li, const Eigen::Vector3d& accel_bias, const char* rotation_deg) {
  const auto motion = sim::load_motion(YAML::Load(
      std::string("{type: sequence, origin: {xyz_m: [0, 0, 1], rpy_deg: [5, -3, 20]}, parts: [{type: static, "
                  "duration_s: 1}, {type: vibration, duration_s: 20, frequency_hz: 0.6, rotation_deg: ") +
      rotation_deg + ", translation_m: [0.1, 0.1, 0.05], fade_s: 1}]}"));
  Recording r;
  const Eigen::Isometry3d T0 = motion->at(0.0).T_wb;
  for (int k = 0; k < 210; ++k) {
    const double t = 0.1 * k;
    r.poses.push_back({t, t, t + 0.099, T0.inverse() * motion->at(t).T_wb, true});
  }
  for (int j = 0; j < 2100; ++j) {
    const double t = 0.0042 + 0.01 * j;
    const sim::ImuKinematics k = sim::imu_kinematics(motion->at(t), T_li);
    ImuSample s;
    s.t_s = t;
    s.gyro_rad_s = k.omega_i;
    s.accel_m_s2 = k.specific_force_i + accel_bias;
    r.imu.push_back(s);
  }
  return r;
}

TEST(RigLeverArm, RecoversTheArmTheAccelerometerBiasAndGravity) {
  const Eigen::Isometry3d T_li = sim::pose_from_xyz_rpy_deg({0.0, 0.03, -0.08}, {180, 0, 90});
  const Eigen::Vector3d bias(0.02, -0.03, 0.01);
  const Recording r = waving(T_li, bias, "[35, 30, 40]");
  const LeverArmEstimate arm = estimate_lever_arm(r.poses, r.imu, GyroModel{T_li.linear(), {}});
  ASSERT_TRUE(arm.solved);
  EXPECT_LT((arm.t_m - T_li.translation()).norm(), 0.002) << arm.t_m.transpose();
  EXPECT_LT((arm.accel_bias_m_s2 - bias).norm(), 0.005) << arm.accel_bias_m_s2.transpose();
  EXPECT_NEAR(arm.gravity_m_s2, 9.80665, 0.01);
  EXPECT_LT(arm.sigma_m.maxCoeff(), 0.002);
}

TEST(RigLeverArm, TurningAboutOneAxisLeavesTheArmAlongItUnobservable) {
  const Eigen::Isometry3d T_li = sim::pose_from_xyz_rpy_deg({0.05, -0.02, 0.1}, {0, 0, 0});
  const Recording r = waving(T_li, Eigen::Vector3d::Zero(), "[0, 0, 40]");
  const LeverArmEstimate arm = estimate_lever_arm(r.poses, r.imu, GyroModel{T_li.linear(), {}});
  // Along z the arm only scales the (zero) centripetal term: singular, or a
  // σ far beyond the others.
  if (arm.solved) {
    EXPECT_GT(arm.sigma_m.z(), 100 * std::max(arm.sigma_m.x(), arm.sigma_m.y()));
  }
}

}  // namespace
}  // namespace tumble::calib
