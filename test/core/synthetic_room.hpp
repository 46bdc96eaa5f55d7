// Analytic test scenes for the registration tests: a closed box room with box
// obstacles, ray-cast exactly, and a 16-ring spinning lidar with per-point times
// moving along any trajectory. Noise-free: expected results are exact.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "core/point_cloud.hpp"
#include "core/types.hpp"

namespace tumble::test {

// Debug builds (the sanitizer trees: ASan at -O1, TSan at -O0) run Eigen
// code tens of times slower: the scene-level tests use coarser clouds there, so that every
// test stays within seconds; optimised builds test at full resolution.
#ifdef NDEBUG
inline constexpr bool kCoarseTests = false;
#else
inline constexpr bool kCoarseTests = true;
#endif
// `full` in optimised builds, `coarse` in unoptimised ones.
template <class T>
constexpr T full_or_coarse(T full, T coarse) {
  return kCoarseTests ? coarse : full;
}

struct Box {
  Eigen::Vector3d lo;
  Eigen::Vector3d hi;
};

struct Room {
  Box interior;
  std::vector<Box> obstacles;

  // Range along the unit ray from o (inside the room) to the first surface.
  double cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
    double best = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {  // leaving the interior
      if (d(a) > 1e-12) best = std::min(best, (interior.hi(a) - o(a)) / d(a));
      if (d(a) < -1e-12) best = std::min(best, (interior.lo(a) - o(a)) / d(a));
    }
    for (const Box& b : obstacles) {  // entering an obstacle
      double t_in = -std::numeric_limits<double>::infinity(), t_out = std::numeric_limits<double>::infinity();
      bool miss = false;
      for (int a = 0; a < 3 && !miss; ++a) {
        if (std::abs(d(a)) < 1e-12) {
          miss = o(a) < b.lo(a) || o(a) > b.hi(a);
          continue;
        }
        double t0 = (b.lo(a) - o(a)) / d(a), t1 = (b.hi(a) - o(a)) / d(a);
        if (t0 > t1) std::swap(t0, t1);
        t_in = std::max(t_in, t0);
        t_out = std::min(t_out, t1);
      }
      if (!miss && t_in <= t_out && t_in > 0) best = std::min(best, t_in);
    }
    return best;
  }
};

// 10 m x 8 m x 3 m with four boxes of different sizes, off-centre so that no
// symmetry makes the registration ambiguous.
inline Room make_room() {
  Room room;
  room.interior = {Eigen::Vector3d(-4, -3, -1), Eigen::Vector3d(6, 5, 2)};
  room.obstacles = {
      {Eigen::Vector3d(2.0, 1.0, -1.0), Eigen::Vector3d(3.0, 2.5, 0.2)},
      {Eigen::Vector3d(-3.0, 3.0, -1.0), Eigen::Vector3d(-2.2, 4.2, 1.0)},
      {Eigen::Vector3d(4.0, -2.5, -1.0), Eigen::Vector3d(5.0, -1.2, -0.3)},
      {Eigen::Vector3d(-1.5, -2.5, 0.5), Eigen::Vector3d(-0.5, -1.8, 1.2)},
  };
  return room;
}

// A corridor along x: two parallel walls and a floor, open along its axis.
inline Room make_corridor() {
  Room room;
  room.interior = {Eigen::Vector3d(-1000, -1.5, -1), Eigen::Vector3d(1000, 1.5, 1000)};
  return room;
}

struct RingLidar {
  int lasers = 16;
  double min_elevation_deg = -15;
  double max_elevation_deg = 15;
  int columns = 1800;  // firings per revolution (0.2 deg at 10 Hz)
  double revolution_s = 0.1;
  double max_range_m = 100;
};

using PoseAt = std::function<Eigen::Isometry3d(double)>;

// One revolution starting at t0_s: every point in the lidar frame at its own
// firing time, as the sensor delivers them, in firing order.
inline std::vector<LidarPoint> scan_room(const Room& room, const PoseAt& T_wl, double t0_s, const RingLidar& lidar = {}) {
  std::vector<LidarPoint> points;
  points.reserve(static_cast<std::size_t>(lidar.lasers * lidar.columns));
  const double deg = M_PI / 180;
  for (int c = 0; c < lidar.columns; ++c) {
    const double t = t0_s + lidar.revolution_s * c / lidar.columns;
    const Eigen::Isometry3d T = T_wl(t);
    const double azimuth = 2 * M_PI * c / lidar.columns;
    for (int l = 0; l < lidar.lasers; ++l) {
      const double elevation =
          (lidar.min_elevation_deg + (lidar.max_elevation_deg - lidar.min_elevation_deg) * l / (lidar.lasers - 1)) * deg;
      const Eigen::Vector3d dir_l(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                                  std::sin(elevation));
      const double range = room.cast(T.translation(), T.linear() * dir_l);
      if (!(range < lidar.max_range_m)) continue;
      const Eigen::Vector3d p = dir_l * range;
      LidarPoint lp;
      lp.t_s = t;
      lp.x_m = static_cast<float>(p.x());
      lp.y_m = static_cast<float>(p.y());
      lp.z_m = static_cast<float>(p.z());
      lp.azimuth_deg = static_cast<float>(azimuth / deg);
      lp.laser = static_cast<std::uint8_t>(l);
      points.push_back(lp);
    }
  }
  return points;
}

// The same, as a registration cloud (positions in double, times and rings kept).
inline PointCloud to_cloud(const std::vector<LidarPoint>& points) {
  PointCloud cloud;
  cloud.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    cloud.points[i] = Eigen::Vector3d(points[i].x_m, points[i].y_m, points[i].z_m);
    cloud.times_s[i] = points[i].t_s;
    cloud.rings[i] = points[i].laser;
  }
  return cloud;
}

// Points on every surface of the room on a regular grid of `spacing_m`, with
// their exact normals (pointing into the free space).
inline PointCloud sample_room_surfaces(const Room& room, double spacing_m) {
  PointCloud cloud;
  auto add_face = [&](const Box& b, int axis, bool high_side, const Eigen::Vector3d& normal) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const int nu = static_cast<int>(std::floor((b.hi(u) - b.lo(u)) / spacing_m));
    const int nv = static_cast<int>(std::floor((b.hi(v) - b.lo(v)) / spacing_m));
    for (int i = 0; i <= nu; ++i)
      for (int j = 0; j <= nv; ++j) {
        Eigen::Vector3d p;
        p(axis) = high_side ? b.hi(axis) : b.lo(axis);
        p(u) = b.lo(u) + i * spacing_m;
        p(v) = b.lo(v) + j * spacing_m;
        cloud.points.push_back(p);
        cloud.normals.push_back(normal);
      }
  };
  for (int a = 0; a < 3; ++a) {
    add_face(room.interior, a, false, Eigen::Vector3d::Unit(a));
    add_face(room.interior, a, true, -Eigen::Vector3d::Unit(a));
    for (const Box& b : room.obstacles) {
      add_face(b, a, false, -Eigen::Vector3d::Unit(a));
      add_face(b, a, true, Eigen::Vector3d::Unit(a));
    }
  }
  const std::size_t n = cloud.points.size();
  cloud.times_s.assign(n, 0.0);
  cloud.rings.assign(n, 0);
  cloud.curvatures.assign(n, 0.0);
  cloud.normal_valid.assign(n, 1);
  cloud.sigma_n_m.assign(n, 0.02);
  cloud.sigma_s_m.assign(n, 0.0);
  cloud.weights.assign(n, 1.0);
  return cloud;
}

inline Eigen::Isometry3d make_pose(const Eigen::Vector3d& t, double roll, double pitch, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = t;
  return T;
}

inline double rotation_error_rad(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

}  // namespace tumble::test
