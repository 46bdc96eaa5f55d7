// Shared by the sensor-model tests: analytic motions with known derivatives,
// a box room whose surfaces are known exactly, scratch folders.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "test/temp_dir.hpp"
#include "tools/sim/motion.hpp"
#include "tools/sim/scenario.hpp"

namespace tumble::sim::test {

using tumble::test::TempDir;

// Constant-rate spin about the world z axis at a fixed point.
class SpinMotion final : public Motion {
 public:
  SpinMotion(Eigen::Vector3d centre, double rate_rad_s, double duration_s)
      : centre_(centre), rate_(rate_rad_s), duration_(duration_s) {}
  MotionState at(double t_s) const override {
    // Written out: this runs once per simulated ray, and tests run unoptimised under ASan.
    const double c = std::cos(rate_ * t_s), s = std::sin(rate_ * t_s);
    MotionState state;
    state.T_wb.matrix() << c, -s, 0, centre_.x(), s, c, 0, centre_.y(), 0, 0, 1, centre_.z(), 0, 0, 0, 1;
    state.omega_b = Eigen::Vector3d(0, 0, rate_);
    return state;
  }
  double duration_s() const override { return duration_; }

 private:
  Eigen::Vector3d centre_;
  double rate_, duration_;
};

// Smooth 3-D motion with every derivative in closed form: position
// p(t) = p0 + A sin(w t + phase) per axis; attitude R(t) = exp([theta(t)]x) with
// theta(t) = B (1 - cos(u t)) about a fixed unit axis k (so omega_b = theta' k,
// alpha_b = theta'' k, exact).
class WobbleMotion final : public Motion {
 public:
  WobbleMotion(double duration_s, Eigen::Vector3d amplitude_m, Eigen::Vector3d rate_rad_s, double tilt_rad,
               double tilt_rate_rad_s, Eigen::Vector3d axis)
      : duration_(duration_s), amplitude_(amplitude_m), w_(rate_rad_s), tilt_(tilt_rad), u_(tilt_rate_rad_s),
        axis_(axis.normalized()) {}
  MotionState at(double t) const override {
    MotionState s;
    Eigen::Vector3d p(1.0, -0.5, 1.2), v, a;
    for (int i = 0; i < 3; ++i) {
      const double phase = w_[i] * t + 0.3 * i;
      p[i] += amplitude_[i] * std::sin(phase);
      v[i] = amplitude_[i] * w_[i] * std::cos(phase);
      a[i] = -amplitude_[i] * w_[i] * w_[i] * std::sin(phase);
    }
    const double theta = tilt_ * (1.0 - std::cos(u_ * t));
    const double theta_dot = tilt_ * u_ * std::sin(u_ * t);
    const double theta_ddot = tilt_ * u_ * u_ * std::cos(u_ * t);
    s.T_wb = Eigen::Translation3d(p) * Eigen::AngleAxisd(theta, axis_);
    s.v_w = v;
    s.a_w = a;
    s.omega_b = theta_dot * axis_;
    s.alpha_b = theta_ddot * axis_;
    return s;
  }
  double duration_s() const override { return duration_; }

 private:
  double duration_;
  Eigen::Vector3d amplitude_, w_;
  double tilt_, u_;
  Eigen::Vector3d axis_;
};

// A closed room of six infinite planes: x in [-5, 6], y in [-4, 3.5], z in [0, 3].
struct BoxRoom {
  Eigen::Vector3d min{-5.0, -4.0, 0.0};
  Eigen::Vector3d max{6.0, 3.5, 3.0};

  // Distance from p to the nearest of the six planes.
  double distance(const Eigen::Vector3d& p) const {
    double d = 1e9;
    for (int i = 0; i < 3; ++i) d = std::min({d, std::abs(p[i] - min[i]), std::abs(p[i] - max[i])});
    return d;
  }

  std::filesystem::path write(const std::filesystem::path& dir) const {
    const auto path = dir / "box_room.yaml";
    std::ofstream out(path);
    out << "name: box_room\nobjects:\n";
    const char* rpy[3] = {"[0, 90, 0]", "[90, 0, 0]", "[0, 0, 0]"};
    for (int i = 0; i < 3; ++i) {
      for (const double c : {min[i], max[i]}) {
        Eigen::Vector3d centre = 0.5 * (min + max);
        centre[i] = c;
        out << "  - {type: plane, reflectivity: 0.6, center_m: [" << centre.x() << ", " << centre.y() << ", "
            << centre.z() << "], rpy_deg: " << rpy[i] << "}\n";
      }
    }
    return path;
  }
};

// A scenario in the box room with a static motion; tests swap in other motions
// through SimRun-free paths or adjust the settings.
inline std::string box_room_scenario_yaml(const std::filesystem::path& scene, double duration_s) {
  return "scene: " + scene.string() + "\nmotion: {type: static, duration_s: " + std::to_string(duration_s) +
         ", origin: {xyz_m: [0.5, -0.3, 1.1]}}\nseed: 7\n";
}

}  // namespace tumble::sim::test
