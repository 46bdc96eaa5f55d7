#include "daemon/viewer_messages.hpp"

#include <algorithm>
#include <cmath>

namespace tumble::daemon {

void fill_viewer_scan(const PointCloud& reading, const Eigen::Isometry3d& T_wl, double t_scan_start_s,
                      std::uint64_t scan_index, tumble::scan_t& scan) {
  const std::size_t n = reading.size();
  scan.utime = std::llround(t_scan_start_s * 1e6);
  scan.scan_index = static_cast<std::int64_t>(scan_index);
  scan.num_points = static_cast<std::int32_t>(n);
  scan.x_m.resize(n);
  scan.y_m.resize(n);
  scan.z_m.resize(n);
  scan.sigma_s_m.resize(n);
  scan.weight.resize(n);
  scan.ring.resize(n);
  const double largest = reading.weights.empty() ? 1.0 : *std::max_element(reading.weights.begin(), reading.weights.end());
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d w = T_wl * reading.points[i];
    scan.x_m[i] = static_cast<float>(w.x());
    scan.y_m[i] = static_cast<float>(w.y());
    scan.z_m[i] = static_cast<float>(w.z());
    scan.sigma_s_m[i] = static_cast<float>(reading.sigma_s_m[i]);
    scan.weight[i] = largest > 0 ? static_cast<float>(reading.weights[i] / largest) : 0.0f;
    scan.ring[i] = static_cast<std::int8_t>(reading.rings[i]);
  }
}

void fill_viewer_map(const LocalMap& map, double t_scan_start_s, std::uint64_t scan_index, std::int32_t resets,
                     tumble::map_t& message) {
  message.utime = std::llround(t_scan_start_s * 1e6);
  message.scan_index = static_cast<std::int64_t>(scan_index);
  message.map_points = static_cast<std::int32_t>(map.size());
  message.points_per_voxel = static_cast<std::int32_t>(kViewerMapPointsPerVoxel);
  message.resets = resets;
  // Capacity for the fullest case with room to grow, so the push_backs
  // below never allocate, and a growing map reallocates only now and then.
  const std::size_t most = std::min(map.size(), map.voxel_count() * kViewerMapPointsPerVoxel);
  for (auto* v : {&message.x_m, &message.y_m, &message.z_m}) {
    v->clear();
    if (v->capacity() < most) v->reserve(most + most / 2);
  }
  map.for_each_voxel_sample(kViewerMapPointsPerVoxel, [&](const Eigen::Vector3d& p) {
    message.x_m.push_back(static_cast<float>(p.x()));
    message.y_m.push_back(static_cast<float>(p.y()));
    message.z_m.push_back(static_cast<float>(p.z()));
  });
  message.num_points = static_cast<std::int32_t>(message.x_m.size());
}

}  // namespace tumble::daemon
