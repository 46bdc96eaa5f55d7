#include "tools/sim/lidar_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/angles.hpp"
#include "drivers/rs16/firing_model.hpp"
#include "drivers/rs16/laser_geometry.hpp"

namespace tumble::sim {
namespace {

const rs16::ChannelTiming kSingleReturnTiming = rs16::channel_timing(rs16::ReturnMode::Strongest);

double wrap_deg(double a) {
  a = std::fmod(a, 360.0);
  return a < 0 ? a + 360.0 : a;
}

}  // namespace

LidarUnit make_lidar_unit(std::uint64_t unit_seed, double vertical_offset_sigma_deg) {
  SensorRng rng(unit_seed, "lidar-unit");
  LidarUnit unit;
  for (std::size_t i = 0; i < unit.vertical_angles_deg.size(); ++i) {
    // Real units stay within a few tenths of a degree of the design angle.
    const double offset = std::clamp(rng.normal(vertical_offset_sigma_deg), -3 * vertical_offset_sigma_deg,
                                     3 * vertical_offset_sigma_deg);
    unit.vertical_angles_deg[i] = std::round((rs16::kDesignVerticalAnglesDeg[i] + offset) * 1e4) / 1e4;
  }
  for (auto& b : unit.serial) b = static_cast<std::uint8_t>(rng.next_u64() & 0xFF);
  return unit;
}

Beam rs16_beam(double azimuth_deg, double vertical_deg) {
  const double ca = std::cos(azimuth_deg * kDegToRad), sa = std::sin(azimuth_deg * kDegToRad);
  const double cw = std::cos(vertical_deg * kDegToRad), sw = std::sin(vertical_deg * kDegToRad);
  return Beam{Eigen::Vector3d(rs16::kOpticalCentreOffset_m * ca, -rs16::kOpticalCentreOffset_m * sa, 0.0),
              Eigen::Vector3d(cw * ca, -cw * sa, sw)};
}

std::array<std::uint16_t, 12> block_azimuths_centideg(double azimuth_at_zero_deg, double motor_deg_per_s,
                                                      std::int64_t first_firing_ns) {
  std::array<std::uint16_t, 12> out{};
  for (int b = 0; b < 12; ++b) {
    const double t_s = static_cast<double>(first_firing_ns + b * kRs16BlockPeriodNs) * 1e-9;
    const double az = wrap_deg(azimuth_at_zero_deg + motor_deg_per_s * t_s);
    out[static_cast<std::size_t>(b)] = static_cast<std::uint16_t>(std::lround(az * 100.0) % 36000);
  }
  return out;
}

double channel_azimuth_deg(const std::array<std::uint16_t, 12>& blocks_centideg, int block, int channel, int rpm) {
  const auto b = static_cast<std::size_t>(std::min(block, 10));  // the last block turns like the one before
  const double step = rs16::interpolation_step(blocks_centideg[b], blocks_centideg[b + 1],
                                               rs16::nominal_block_step(rpm, rs16::ReturnMode::Strongest));
  return (blocks_centideg[static_cast<std::size_t>(block)] +
          step * kSingleReturnTiming.azimuth_fraction[static_cast<std::size_t>(channel)]) /
         100.0;
}

LidarModel::LidarModel(const LidarConfig& config, const LidarUnit& unit, const Scene& scene, const Motion& motion,
                       std::uint64_t noise_seed, double azimuth_at_zero_deg)
    : config_(config),
      unit_(unit),
      scene_(scene),
      motion_(motion),
      rng_(noise_seed, "lidar-returns"),
      azimuth_at_zero_deg_(azimuth_at_zero_deg),
      motor_deg_per_s_(config.rpm * 6.0) {}

void LidarModel::fill_packet(std::int64_t first_firing_ns, rs16::MsopPacketData& out) {
  const auto blocks = block_azimuths_centideg(azimuth_at_zero_deg_, motor_deg_per_s_, first_firing_ns);
  out.temperature_c = config_.temperature_c;
  for (int b = 0; b < 12; ++b) {
    auto& block = out.blocks[static_cast<std::size_t>(b)];
    block.azimuth_deg = blocks[static_cast<std::size_t>(b)] / 100.0;
    for (int c = 0; c < 32; ++c) {
      const std::int64_t t_ns = first_firing_ns + b * kRs16BlockPeriodNs + (c / 16) * kRs16SequencePeriodNs +
                                (c % 16) * kRs16LaserSpacingNs;
      block.channels[static_cast<std::size_t>(c)] =
          fire(static_cast<double>(t_ns) * 1e-9, channel_azimuth_deg(blocks, b, c, config_.rpm), c % 16);
    }
  }
}

rs16::ChannelReturn LidarModel::fire(double t_s, double azimuth_deg, int laser) {
  const Beam beam = rs16_beam(azimuth_deg, unit_.vertical_angles_deg[static_cast<std::size_t>(laser)]);
  const Eigen::Isometry3d T_wl = motion_.at(t_s).T_wb;
  const Eigen::Vector3d direction_w = T_wl.linear() * beam.direction_l;
  // Noise can push a return past max range or below min range: cast a little
  // further so the limits act on what the unit measures.
  const double cast_limit_m = config_.max_range_m + 5.0 * config_.range_noise_m;
  const auto hit = scene_.cast(T_wl * beam.origin_l, direction_w, cast_limit_m);
  // Draw the noise for every firing so one return's fate never shifts the
  // noise of the next (keeps runs comparable when a scene changes slightly).
  const double noise_m = rng_.normal(config_.range_noise_m);
  const bool dropped = rng_.chance(config_.dropout_probability);
  if (!hit || dropped) return {};
  const double range_m = hit->range_m + noise_m;
  if (range_m < config_.min_range_m || range_m > config_.max_range_m) return {};
  const double cos_incidence = std::min(1.0, std::abs(direction_w.dot(hit->normal_w)));
  // 0..100 is the unit's diffuse scale; retro-reflectors (reflectivity > 1) go above.
  const double reflectivity = 100.0 * hit->reflectivity * std::pow(cos_incidence, config_.incidence_falloff_exponent);
  const auto reflectivity_u8 = static_cast<std::uint8_t>(std::clamp(std::lround(reflectivity), 1L, 255L));
  return rs16::ChannelReturn{range_m, reflectivity_u8};
}

}  // namespace tumble::sim
