#include "tools/view/frames.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <utility>
#include <vector>

namespace tumble::view {
namespace {

// JSON has no NaN or infinity: a value not measured is null.
std::string number(double v) { return std::isfinite(v) ? fmt::format("{}", v) : "null"; }

template <class T>
std::string numbers(const T* v, std::size_t n) {
  std::string out = "[";
  for (std::size_t i = 0; i < n; ++i) {
    if (i) out += ',';
    out += number(static_cast<double>(v[i]));
  }
  return out + "]";
}

Frame text(FrameKind kind, bool newest_only, std::string json) { return {kind, false, newest_only, std::move(json)}; }

void append_u32(std::string& out, std::uint32_t v) {
  char b[4];
  std::memcpy(b, &v, 4);
  out.append(b, 4);
}

// Every stride-th value of `values` as float32.
template <class T>
void append_strided(std::string& out, const std::vector<T>& values, std::size_t stride, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    const auto v = static_cast<float>(values[i * stride]);
    char b[4];
    std::memcpy(b, &v, 4);
    out.append(b, 4);
  }
}

std::size_t stride_for(std::size_t n, std::size_t max_points) { return n <= max_points ? 1 : (n + max_points - 1) / max_points; }

}  // namespace

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

Frame status_frame(const tumble::status_t& s) {
  std::string j = fmt::format(R"({{"type":"status","utime":{},"state":{},"state_name":{},"reason":{},"uptime_s":{},)",
                              s.utime, static_cast<int>(s.state), json_string(s.state_name),
                              json_string(s.state_reason), number(s.uptime_s));
  j += fmt::format(R"j("rates":{{"lidar packets (Hz)":{},"IMU (Hz)":{},"scans (Hz)":{}}},)j",
                   number(s.lidar_packet_rate_hz), number(s.imu_rate_hz), number(s.scan_rate_hz));
  j += fmt::format(R"("expected_error_max_m":{},"resets":{},)", number(s.expected_error_max_m), s.resets);
  j += fmt::format(
      R"j("latency":{{"odometry p50 (ms)":{},"odometry p99 (ms)":{},"odometry max (ms)":{},"pose p50 (ms)":{},)j"
      R"j("pose max (ms)":{}}},)j",
      number(s.odometry_latency_p50_ms), number(s.odometry_latency_p99_ms), number(s.odometry_latency_max_ms),
      number(s.pose_latency_p50_ms), number(s.pose_latency_max_ms));
  const std::pair<const char*, std::int64_t> counters[] = {
      {"lidar_packets", s.lidar_packets},
      {"lidar_bad_packets", s.lidar_bad_packets},
      {"lidar_missing_packets", s.lidar_missing_packets},
      {"lidar_foreign_packets", s.lidar_foreign_packets},
      {"lidar_duplicate_packets", s.lidar_duplicate_packets},
      {"lidar_late_packets", s.lidar_late_packets},
      {"lidar_late_packets_dropped", s.lidar_late_packets_dropped},
      {"lidar_difop_ignored", s.lidar_difop_ignored},
      {"imu_frames", s.imu_frames},
      {"imu_bad_frames", s.imu_bad_frames},
      {"imu_gaps", s.imu_gaps},
      {"imu_duplicate_frames", s.imu_duplicate_frames},
      {"imu_out_of_order_frames", s.imu_out_of_order_frames},
      {"imu_rejected_samples", s.imu_rejected_samples},
      {"scans_registered", s.scans_registered},
      {"scans_dropped", s.scans_dropped},
      {"scans_short_coverage", s.scans_short_coverage},
      {"scans_cut_at_bound", s.scans_cut_at_bound},
      {"scans_short_trajectory", s.scans_short_trajectory},
      {"scans_imu_bridged", s.scans_imu_bridged},
      {"scans_untrusted", s.scans_untrusted},
      {"scans_spin_rate_unmeasured", s.scans_spin_rate_unmeasured},
      {"scans_weakly_constrained", s.scans_weakly_constrained},
      {"scans_map_deferred", s.scans_map_deferred},
      {"scans_jumped", s.scans_jumped},
      {"scans_awaiting_rest", s.scans_awaiting_rest},
      {"accel_saturated_samples", s.accel_saturated_samples[0] + s.accel_saturated_samples[1] + s.accel_saturated_samples[2]},
      {"gyro_saturated_samples", s.gyro_saturated_samples[0] + s.gyro_saturated_samples[1] + s.gyro_saturated_samples[2]},
  };
  j += R"("counters":{)";
  for (std::size_t i = 0; i < std::size(counters); ++i)
    j += fmt::format(R"({}"{}":{})", i ? "," : "", counters[i].first, counters[i].second);
  j += R"(},"stages":[)";
  const auto stages = static_cast<std::size_t>(std::max<int>(s.num_stages, 0));
  for (std::size_t i = 0; i < stages; ++i)
    j += fmt::format(R"({}[{},{},{}])", i ? "," : "", json_string(s.stage_name[i]), number(s.stage_median_ms[i]),
                     number(s.stage_max_ms[i]));
  j += R"(],"rings":[)";
  const auto rings = static_cast<std::size_t>(std::max<int>(s.num_rings, 0));
  for (std::size_t i = 0; i < rings; ++i)
    j += fmt::format(R"({}[{},{},{}])", i ? "," : "", json_string(s.ring_name[i]), number(s.ring_fill[i]),
                     s.ring_drops[i]);
  j += "]}";
  return text(FrameKind::kStatus, true, std::move(j));
}

Frame pose_frame(const tumble::registration_t& r) {
  std::string j = fmt::format(
      R"({{"type":"pose","utime":{},"scan_index":{},"p":{},"q":{},"registered":{},"expected_error_m":{},)"
      R"("inlier_ratio":{},"residual_m":{},"iterations":{},"resets":{},"latency_ms":{},"model":{},"stages":[)",
      r.utime, r.scan_index, numbers(r.position_m, 3), numbers(r.orientation, 4), r.registered ? "true" : "false",
      number(r.expected_error_m), number(r.inlier_ratio), number(r.residual_m), r.iterations, r.resets,
      number(r.latency_ms), json_string(r.model));
  const auto stages = static_cast<std::size_t>(std::max<int>(r.num_stages, 0));
  for (std::size_t i = 0; i < stages; ++i)
    j += fmt::format(R"({}[{},{}])", i ? "," : "", json_string(r.stage_name[i]), number(r.stage_ms[i]));
  j += "]}";
  return text(FrameKind::kPose, false, std::move(j));
}

Frame odometry_frame(const tumble::odometry_t& o) {
  return text(FrameKind::kOdometry, true,
              fmt::format(R"({{"type":"odometry","utime":{},"p":{},"q":{},"v":{},"flags":{},"resets":{}}})", o.utime,
                          numbers(o.position_m, 3), numbers(o.orientation, 4), numbers(o.velocity_m_s, 3), o.flags,
                          o.resets));
}

Frame scan_frame(const tumble::scan_t& s) {
  const auto total = static_cast<std::size_t>(std::max(s.num_points, 0));
  const std::size_t stride = stride_for(total, kMaxScanPoints);
  const std::size_t n = total / stride;
  Frame f{FrameKind::kScan, true, true, {}};
  f.bytes.reserve(16 + n * 6 * 4);
  f.bytes.append("SCAN", 4);
  append_u32(f.bytes, static_cast<std::uint32_t>(n));
  append_u32(f.bytes, static_cast<std::uint32_t>(s.scan_index));
  append_u32(f.bytes, static_cast<std::uint32_t>(stride));
  append_strided(f.bytes, s.x_m, stride, n);
  append_strided(f.bytes, s.y_m, stride, n);
  append_strided(f.bytes, s.z_m, stride, n);
  append_strided(f.bytes, s.sigma_s_m, stride, n);
  append_strided(f.bytes, s.weight, stride, n);
  append_strided(f.bytes, s.ring, stride, n);
  return f;
}

Frame map_frame(const tumble::map_t& m) {
  const auto total = static_cast<std::size_t>(std::max(m.num_points, 0));
  const std::size_t stride = stride_for(total, kMaxMapPoints);
  const std::size_t n = total / stride;
  Frame f{FrameKind::kMap, true, true, {}};
  f.bytes.reserve(16 + n * 3 * 4);
  f.bytes.append("MAP_", 4);
  append_u32(f.bytes, static_cast<std::uint32_t>(n));
  append_u32(f.bytes, static_cast<std::uint32_t>(m.map_points));
  append_u32(f.bytes, static_cast<std::uint32_t>(stride));
  append_strided(f.bytes, m.x_m, stride, n);
  append_strided(f.bytes, m.y_m, stride, n);
  append_strided(f.bytes, m.z_m, stride, n);
  return f;
}

Frame link_frame(const LinkReport& l) {
  return text(FrameKind::kLink, true,
              fmt::format(R"({{"type":"link","lcm_url":{},"channel_prefix":{},"messages":{},"since_last_s":{},"browsers":{}}})",
                          json_string(l.lcm_url), json_string(l.channel_prefix), l.messages,
                          l.since_last_s < 0 ? std::string("null") : number(l.since_last_s), l.browsers));
}

Frame history_frame(std::span<const float> xyz) {
  std::string j = R"({"type":"history","p":)";
  j += numbers(xyz.data(), xyz.size());
  j += "}";
  return text(FrameKind::kHistory, false, std::move(j));
}

}  // namespace tumble::view
