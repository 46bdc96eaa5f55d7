// The RS-16 as a sensor: which ray each laser fires when, what it measures,
// and the MSOP packet that carries it (single return, docs/sensors.md). Every return
// is cast from the lidar pose at its own firing time, so motion skews the
// scan exactly as it does on the real unit.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>

#include "drivers/rs16/msop_encode.hpp"
#include "tools/sim/motion.hpp"
#include "tools/sim/people.hpp"
#include "tools/sim/scene.hpp"
#include "tools/sim/sensor_rng.hpp"

namespace tumble::sim {

// Firing pattern of docs/sensors.md, in nanoseconds (all exact on a 100 ns grid).
inline constexpr std::int64_t kRs16LaserSpacingNs = 2'800;
inline constexpr std::int64_t kRs16SequencePeriodNs = 55'500;
inline constexpr std::int64_t kRs16BlockPeriodNs = 2 * kRs16SequencePeriodNs;
inline constexpr std::int64_t kRs16PacketPeriodNs = 12 * kRs16BlockPeriodNs;
// From the packet's first firing (its header time) to its last.
inline constexpr std::int64_t kRs16PacketSpanNs = 11 * kRs16BlockPeriodNs + kRs16SequencePeriodNs + 15 * kRs16LaserSpacingNs;

// The robot's own body in the lidar frame: bars of a rolling cage, parallel to
// its roll axis on a circle around it, fixed in frame B (the lidar turns with
// the cage). A beam that meets a bar stops there: a return if the bar is
// beyond min_range_m, none (a lost point) if it is nearer.
struct CageBars {
  bool enabled = false;
  int count = 8;
  double cage_radius_m = 0.3;  // the bench's cage (bench.cpp)
  double bar_radius_m = 0.01;  // 20 mm tube
  double length_m = 0.6;
  Eigen::Vector3d axis_l = Eigen::Vector3d::UnitY();  // the roll axis in L
  Eigen::Vector3d centre_l = Eigen::Vector3d::Zero(); // the cage centre in L
  double reflectivity = 0.3;                          // painted steel
};

struct LidarConfig {
  int rpm = 600;                           // 300, 600 or 1200
  double range_noise_m = 0.02;             // 1 sigma, along the beam
  double min_range_m = 0.4;
  double max_range_m = 150.0;
  double dropout_probability = 0.005;      // returns lost at random
  double incidence_falloff_exponent = 1.0;  // reflectivity ~ surface * cos(incidence)^k
  double vertical_offset_sigma_deg = 0.1;  // per-unit deviation of each laser from its design angle
  double temperature_c = 38.0;

  // Error sources beyond noise and the vertical angles, each off unless a
  // scenario turns it on (today's runs stay as they were). Source: RS-LiDAR-16
  // user manual (v4.x), §2 specifications: range accuracy "up to +-2 cm
  // (typical)", measurement range 150 m on a 20 % reflective target.
  // Per-laser range offset left by the unit's calibration: each laser
  // reads N(0, sigma) long, clamped at 3 sigma, the same for every run of a
  // unit. sigma = 1 cm puts the manual's +-2 cm at 2 sigma.
  bool range_offset_error = false;
  double range_offset_sigma_m = 0.01;
  // Range walk of the threshold detector: a weak echo crosses the threshold
  // late and reads long, a strong one short. The range bias is
  // walk * (0.5 - effective reflectivity), so the spread between a black and a
  // white diffuse surface is the manual's 2 cm accuracy.
  bool intensity_range_bias = false;
  double intensity_range_walk_m = 0.02;
  // Dark surfaces: the echo of a diffuse target of reflectivity r falls as
  // r / d^2, so the unit sees it out to 150 m * sqrt(r / 0.2) (the manual's
  // range at 20 %); beyond, no return. r includes the incidence falloff.
  bool dark_surface_dropout = false;
  double range_at_reference_reflectivity_m = 150.0;
  double reference_reflectivity = 0.2;
  CageBars cage_bars;
  // Mixed pixels at depth edges: the beam is a cone, not a line. Where its
  // footprint straddles a depth edge, the echoes of the near and the far
  // surface overlap in time and the detector reports one range between them,
  // weighted by the energy from each; surfaces further apart than
  // mixed_pixel_max_gap_m give separate echoes and the stronger one is
  // reported (the unit's strongest-return mode). The footprint is sampled by
  // five rays (centre and the four edges of the divergence cone, equal
  // weights), so this costs four extra casts per beam, and only when on.
  // Divergence: the RS-16 manual (v4.x) gives none. These are Velodyne's
  // figures for its spinning 905 nm units (VLS-128 user manual, appendix F.2.3,
  // table F-1: 3.0 mrad (0.18 deg) horizontal, 1.5 mrad (0.09 deg) vertical,
  // horizontal about twice vertical), taken for the RS-16 until its own are known.
  // The gap is c * pulse width / 2 for a ~10 ns pulse (an assumption: the
  // manual gives no pulse width either).
  bool mixed_pixels = false;
  double beam_divergence_horizontal_mrad = 3.0;
  double beam_divergence_vertical_mrad = 1.5;
  double mixed_pixel_max_gap_m = 1.5;
};

// What makes one physical unit differ from the design: drawn once per unit seed.
struct LidarUnit {
  std::array<double, 16> vertical_angles_deg{};  // on the DIFOP's 0.0001 deg grid
  std::array<std::uint8_t, 6> serial{};
  std::array<double, 16> range_offsets_m{};  // zero unless range_offset_error
};
LidarUnit make_lidar_unit(std::uint64_t unit_seed, const LidarConfig& config);

// The beam of one firing in the lidar frame: it leaves the optical centre,
// R = 0.03825 m out along the azimuth, so that the decoder's
// x = d cos w cos a + R cos a, y = -d cos w sin a - R sin a, z = d sin w
// is exactly origin + d * direction.
struct Beam {
  Eigen::Vector3d origin_l;
  Eigen::Vector3d direction_l;  // unit
};
Beam rs16_beam(double azimuth_deg, double vertical_deg);

// Block azimuths in the packet's 0.01 deg units, as the motor encoder reads
// them at each block's first firing.
std::array<std::uint16_t, 12> block_azimuths_centideg(double azimuth_at_zero_deg, double motor_deg_per_s,
                                                      std::int64_t first_firing_ns);
// The azimuth the decoder assigns to channel c of block b (docs/sensors.md's
// interpolation, including its last-block and FOV-gap rules), so that the
// simulated beam is the one the decoder will reconstruct.
double channel_azimuth_deg(const std::array<std::uint16_t, 12>& blocks_centideg, int block, int channel, int rpm);

class LidarModel {
 public:
  // azimuth_at_zero_deg: where the motor points at t = 0 (it is already spinning).
  // people (may be null: nobody) move in the scene; they must outlive the model.
  LidarModel(const LidarConfig& config, const LidarUnit& unit, const Scene& scene, const Motion& motion,
             std::uint64_t noise_seed, double azimuth_at_zero_deg, const People* people = nullptr);

  // The packet whose first firing is at first_firing_ns (run time); utc_time_ns
  // is left for the caller's clock. Every firing must lie inside the motion.
  void fill_packet(std::int64_t first_firing_ns, rs16::MsopPacketData& out);

 private:
  rs16::ChannelReturn fire(double t_s, double azimuth_deg, int laser);
  // The nearest surface a beam fired at t_s returns from: the world (through
  // glass, not from a mirror seen off-normal), a person, or the robot's body.
  std::optional<Hit> first_return(double t_s, const Eigen::Isometry3d& T_wl, const Beam& beam, double limit_m) const;
  // What the whole footprint of the beam returns (mixed_pixels): the centre
  // ray's hit where the footprint lies on one surface, else the merged or
  // the strongest echo.
  std::optional<Hit> footprint_return(double t_s, const Eigen::Isometry3d& T_wl, double azimuth_deg,
                                      double vertical_deg, double limit_m) const;

  LidarConfig config_;
  LidarUnit unit_;
  const Scene& scene_;
  Scene body_;  // the cage bars in L; empty when off
  const Motion& motion_;
  const People* people_;  // null or empty: nobody
  SensorRng rng_;
  double azimuth_at_zero_deg_;
  double motor_deg_per_s_;
};

}  // namespace tumble::sim
