#include "tools/sim/lidar_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/angles.hpp"
#include "drivers/rs16/firing_model.hpp"
#include "drivers/rs16/laser_geometry.hpp"

namespace tumble::sim {
namespace {

// Scene objects of material specular return only within this angle of normal
// incidence, about the beam's own divergence (elsewhere the beam is reflected
// away from the sensor); glass lets it through to what is behind.
constexpr double kSpecularLobeDeg = 2.0;

const rs16::ChannelTiming kSingleReturnTiming = rs16::channel_timing(rs16::ReturnMode::Strongest);

double wrap_deg(double a) {
  a = std::fmod(a, 360.0);
  return a < 0 ? a + 360.0 : a;
}

// The cage bars as cylinders in L, evenly around the roll axis.
Scene cage_bar_scene(const CageBars& bars) {
  if (!bars.enabled) return Scene();
  const Eigen::Vector3d axis = bars.axis_l.normalized();
  const Eigen::Vector3d across = axis.unitOrthogonal();
  const Eigen::Vector3d third = axis.cross(across);
  std::vector<Primitive> primitives;
  for (int k = 0; k < bars.count; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / bars.count;
    Primitive bar;
    bar.shape = Shape::Cylinder;
    bar.radius_m = bars.bar_radius_m;
    bar.half_size.z() = 0.5 * bars.length_m;
    bar.reflectivity = bars.reflectivity;
    bar.pose_w.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis).toRotationMatrix();
    bar.pose_w.translation() = bars.centre_l + bars.cage_radius_m * (std::cos(phi) * across + std::sin(phi) * third);
    bar.name = "cage bar " + std::to_string(k);
    primitives.push_back(bar);
  }
  return Scene(std::move(primitives), "cage bars");
}

}  // namespace

LidarUnit make_lidar_unit(std::uint64_t unit_seed, const LidarConfig& config) {
  const double vertical_offset_sigma_deg = config.vertical_offset_sigma_deg;
  SensorRng rng(unit_seed, "lidar-unit");
  LidarUnit unit;
  for (std::size_t i = 0; i < unit.vertical_angles_deg.size(); ++i) {
    // Real units stay within a few tenths of a degree of the design angle.
    const double offset = std::clamp(rng.normal(vertical_offset_sigma_deg), -3 * vertical_offset_sigma_deg,
                                     3 * vertical_offset_sigma_deg);
    unit.vertical_angles_deg[i] = std::round((rs16::kDesignVerticalAnglesDeg[i] + offset) * 1e4) / 1e4;
  }
  for (auto& b : unit.serial) b = static_cast<std::uint8_t>(rng.next_u64() & 0xFF);
  if (config.range_offset_error) {
    SensorRng offsets(unit_seed, "lidar-unit-range-offset");
    const double sigma = config.range_offset_sigma_m;
    for (auto& o : unit.range_offsets_m) o = std::clamp(offsets.normal(sigma), -3 * sigma, 3 * sigma);
  }
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
                       std::uint64_t noise_seed, double azimuth_at_zero_deg, const People* people)
    : config_(config),
      unit_(unit),
      scene_(scene),
      body_(cage_bar_scene(config.cage_bars)),
      motion_(motion),
      people_(people != nullptr && !people->empty() ? people : nullptr),
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

std::optional<Hit> LidarModel::first_return(double t_s, const Eigen::Isometry3d& T_wl, const Beam& beam,
                                            double limit_m) const {
  const Eigen::Vector3d direction_w = T_wl.linear() * beam.direction_l;
  const Eigen::Vector3d beam_origin_w = T_wl * beam.origin_l;
  Eigen::Vector3d origin_w = beam_origin_w;
  double travelled_m = 0.0;
  std::optional<Hit> hit;
  // Through glass panes one after another (a few at most in any scene).
  for (int pane = 0; pane < 8; ++pane) {
    hit = scene_.cast(origin_w, direction_w, limit_m - travelled_m);
    if (!hit || hit->material != Material::Glass) break;
    constexpr double kPastThePane_m = 1e-6;
    travelled_m += hit->range_m + kPastThePane_m;
    origin_w += (hit->range_m + kPastThePane_m) * direction_w;
    hit.reset();
  }
  if (hit) hit->range_m += travelled_m;
  if (people_ != nullptr) {
    // People stand in front of whatever the world returns (or would reflect away).
    if (auto person = people_->cast(t_s, beam_origin_w, direction_w, hit ? hit->range_m : limit_m)) hit = person;
  }
  if (hit) {
    if (hit->material == Material::Specular &&
        std::abs(direction_w.dot(hit->normal_w)) < std::cos(kSpecularLobeDeg * kDegToRad)) {
      hit.reset();
    }
  }
  if (!body_.primitives().empty()) {
    // The body is fixed in L: cast there; the normal goes to W for the incidence.
    if (auto bar = body_.cast(beam.origin_l, beam.direction_l, hit ? hit->range_m : limit_m)) {
      bar->normal_w = T_wl.linear() * bar->normal_w;
      hit = bar;
    }
  }
  return hit;
}

std::optional<Hit> LidarModel::footprint_return(double t_s, const Eigen::Isometry3d& T_wl, double azimuth_deg,
                                                double vertical_deg, double limit_m) const {
  // Below this depth spread the footprint is on one surface (a slanted one
  // spreads a few cm): the centre ray stands for it.
  constexpr double kEdgeGap_m = 0.1;
  constexpr std::size_t kRays = 5;
  const double half_h_deg = 0.5e-3 * config_.beam_divergence_horizontal_mrad / kDegToRad;
  const double half_v_deg = 0.5e-3 * config_.beam_divergence_vertical_mrad / kDegToRad;
  const std::array<Beam, kRays> rays = {
      rs16_beam(azimuth_deg, vertical_deg), rs16_beam(azimuth_deg - half_h_deg, vertical_deg),
      rs16_beam(azimuth_deg + half_h_deg, vertical_deg), rs16_beam(azimuth_deg, vertical_deg - half_v_deg),
      rs16_beam(azimuth_deg, vertical_deg + half_v_deg)};
  std::array<std::optional<Hit>, kRays> hits;
  double nearest_m = std::numeric_limits<double>::infinity(), farthest_m = 0.0;
  std::size_t returns = 0;
  for (std::size_t i = 0; i < kRays; ++i) {
    hits[i] = first_return(t_s, T_wl, rays[i], limit_m);
    if (!hits[i]) continue;
    ++returns;
    nearest_m = std::min(nearest_m, hits[i]->range_m);
    farthest_m = std::max(farthest_m, hits[i]->range_m);
  }
  if (returns == 0) return std::nullopt;
  if (returns == kRays && farthest_m - nearest_m < kEdgeGap_m) return hits[0];

  // Echo energy of each part of the footprint: its share of the beam times
  // the surface's effective reflectivity over range squared.
  const double share = 1.0 / kRays;
  std::array<double, kRays> energy{};
  for (std::size_t i = 0; i < kRays; ++i) {
    if (!hits[i]) continue;
    const Eigen::Vector3d direction_w = T_wl.linear() * rays[i].direction_l;
    const double cos_incidence = std::min(1.0, std::abs(direction_w.dot(hits[i]->normal_w)));
    energy[i] = share * hits[i]->reflectivity * std::pow(cos_incidence, config_.incidence_falloff_exponent) /
                std::max(hits[i]->range_m * hits[i]->range_m, 1e-6);
  }
  // The near echo (everything within the gap of the nearest surface) and the far one.
  const auto in_near = [&](std::size_t i) { return hits[i]->range_m <= nearest_m + config_.mixed_pixel_max_gap_m; };
  double near_energy = 0.0, far_energy = 0.0;
  for (std::size_t i = 0; i < kRays; ++i) {
    if (hits[i]) (in_near(i) ? near_energy : far_energy) += energy[i];
  }
  const bool take_near = near_energy >= far_energy;
  double weighted_range = 0.0, weight = 0.0, reflectivity = 0.0;
  std::size_t strongest = kRays;
  for (std::size_t i = 0; i < kRays; ++i) {
    if (!hits[i] || in_near(i) != take_near) continue;
    weighted_range += energy[i] * hits[i]->range_m;
    weight += energy[i];
    reflectivity += share * hits[i]->reflectivity;  // a part of the footprint echoes less
    if (strongest == kRays || energy[i] > energy[strongest]) strongest = i;
  }
  Hit merged = *hits[strongest];
  merged.range_m = weight > 0.0 ? weighted_range / weight : merged.range_m;
  merged.reflectivity = reflectivity;
  return merged;
}

rs16::ChannelReturn LidarModel::fire(double t_s, double azimuth_deg, int laser) {
  const auto laser_index = static_cast<std::size_t>(laser);
  const Beam beam = rs16_beam(azimuth_deg, unit_.vertical_angles_deg[laser_index]);
  const Eigen::Isometry3d T_wl = motion_.at(t_s).T_wb;
  const Eigen::Vector3d direction_w = T_wl.linear() * beam.direction_l;
  // Noise can push a return past max range or below min range: cast a little
  // further so the limits act on what the unit measures.
  const double cast_limit_m = config_.max_range_m + 5.0 * config_.range_noise_m;
  const auto hit = config_.mixed_pixels
                       ? footprint_return(t_s, T_wl, azimuth_deg, unit_.vertical_angles_deg[laser_index], cast_limit_m)
                       : first_return(t_s, T_wl, beam, cast_limit_m);
  // Draw the noise for every firing so one return's fate never shifts the
  // noise of the next (keeps runs comparable when a scene changes slightly).
  const double noise_m = rng_.normal(config_.range_noise_m);
  const bool dropped = rng_.chance(config_.dropout_probability);
  if (!hit || dropped) return {};
  const double cos_incidence = std::min(1.0, std::abs(direction_w.dot(hit->normal_w)));
  // 0..100 is the unit's diffuse scale; retro-reflectors (reflectivity > 1) go above.
  const double reflectivity = 100.0 * hit->reflectivity * std::pow(cos_incidence, config_.incidence_falloff_exponent);
  const double effective_reflectivity = reflectivity / 100.0;
  if (config_.dark_surface_dropout &&
      hit->range_m > config_.range_at_reference_reflectivity_m *
                         std::sqrt(effective_reflectivity / config_.reference_reflectivity)) {
    return {};
  }
  double range_m = hit->range_m + noise_m + unit_.range_offsets_m[laser_index];
  if (config_.intensity_range_bias) {
    range_m += config_.intensity_range_walk_m * (0.5 - std::min(effective_reflectivity, 1.0));
  }
  if (range_m < config_.min_range_m || range_m > config_.max_range_m) return {};
  const auto reflectivity_u8 = static_cast<std::uint8_t>(std::clamp(std::lround(reflectivity), 1L, 255L));
  return rs16::ChannelReturn{range_m, reflectivity_u8};
}

}  // namespace tumble::sim
