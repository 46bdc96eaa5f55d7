// The RS-16 error sources beyond noise and the vertical angles (LidarConfig)
// and the scene's surface materials: each is absent when off and, when on,
// has the configured magnitude. Checked on single packets of a lidar at rest
// in front of known walls (a packet spans 4.8 deg of azimuth around +x).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/angles.hpp"
#include "test/tools/sim/sensor_test_support.hpp"
#include "tools/sim/lidar_model.hpp"
#include "tools/sim/scene_load.hpp"
#include "tools/sim/sim_config_error.hpp"

namespace tumble::sim {
namespace {

using test::SpinMotion;


// A wall x = distance facing the lidar at the origin.
Primitive facing_wall(double distance_m, double reflectivity, Material material = Material::Diffuse) {
  Primitive p;
  p.shape = Shape::Plane;
  p.pose_w = Eigen::Translation3d(distance_m, 0, 0) * Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY());
  p.reflectivity = reflectivity;
  p.material = material;
  return p;
}

// A noiseless, dropout-free unit at rest at the origin.
LidarConfig exact_unit_config() {
  LidarConfig c;
  c.range_noise_m = 0.0;
  c.dropout_probability = 0.0;
  return c;
}

struct Firing {
  int laser;
  rs16::ChannelReturn ret;
};

std::vector<Firing> one_packet(const Scene& scene, const LidarConfig& config, const LidarUnit& unit) {
  const SpinMotion still({0, 0, 0}, 0.0, 1.0);
  LidarModel model(config, unit, scene, still, 1, 357.6);
  rs16::MsopPacketData packet;
  model.fill_packet(0, packet);
  std::vector<Firing> out;
  for (const auto& block : packet.blocks)
    for (int c = 0; c < 32; ++c) out.push_back({c % 16, block.channels[static_cast<std::size_t>(c)]});
  return out;
}

TEST(LidarRangeOffset, EachLaserReadsLongByItsOwnCalibrationError) {
  LidarConfig on = exact_unit_config();
  on.range_offset_error = true;
  std::vector<double> offsets;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const LidarUnit unit = make_lidar_unit(seed, on);
    // The vertical angles are the same unit's with or without the source.
    EXPECT_EQ(unit.vertical_angles_deg, make_lidar_unit(seed, exact_unit_config()).vertical_angles_deg);
    for (const double o : unit.range_offsets_m) {
      EXPECT_LE(std::abs(o), 0.03 + 1e-12);
      offsets.push_back(o);
    }
  }
  double sq = 0.0;
  for (const double o : offsets) sq += o * o;
  EXPECT_NEAR(std::sqrt(sq / static_cast<double>(offsets.size())), 0.01, 0.001);
  for (const double o : make_lidar_unit(1, exact_unit_config()).range_offsets_m) EXPECT_EQ(o, 0.0);

  const Scene scene({facing_wall(8.0, 0.5)});
  const LidarUnit unit = make_lidar_unit(3, on);
  const auto with = one_packet(scene, on, unit),
             without = one_packet(scene, exact_unit_config(), make_lidar_unit(3, exact_unit_config()));
  ASSERT_EQ(with.size(), without.size());
  for (std::size_t i = 0; i < with.size(); ++i) {
    ASSERT_GT(without[i].ret.distance_m, 0.0);
    EXPECT_NEAR(with[i].ret.distance_m - without[i].ret.distance_m,
                unit.range_offsets_m[static_cast<std::size_t>(with[i].laser)], 1e-9);
  }
}

TEST(LidarIntensityRangeBias, DarkReadsLongAndBrightShort) {
  LidarConfig on = exact_unit_config();
  on.intensity_range_bias = true;
  const LidarUnit unit = make_lidar_unit(3, exact_unit_config());
  for (const double reflectivity : {0.05, 0.5, 0.95}) {
    const Scene scene({facing_wall(6.0, reflectivity)});
    const auto with = one_packet(scene, on, unit), without = one_packet(scene, exact_unit_config(), unit);
    for (std::size_t i = 0; i < with.size(); ++i) {
      // The effective reflectivity is on the unit's 1 % grid: 0.005 of slack.
      const double expected = 0.02 * (0.5 - without[i].ret.reflectivity / 100.0);
      EXPECT_NEAR(with[i].ret.distance_m - without[i].ret.distance_m, expected, 0.02 * 0.005 + 1e-12);
    }
    const double first = with[0].ret.distance_m - without[0].ret.distance_m;
    if (reflectivity < 0.2) {
      EXPECT_GT(first, 0.005);
    } else if (reflectivity > 0.8) {
      EXPECT_LT(first, -0.005);
    }
  }
}

TEST(LidarDarkSurfaces, AreSeenOnlyAsFarAsTheirEchoAllows) {
  LidarConfig on = exact_unit_config();
  on.dark_surface_dropout = true;
  const LidarUnit unit = make_lidar_unit(3, exact_unit_config());
  // 150 m * sqrt(0.002 / 0.2) = 15 m: a black wall at 20 m is out of reach,
  // at 10 m in reach; a grey one at 20 m too.
  const auto count_returns = [&](const Scene& scene, const LidarConfig& config) {
    int n = 0;
    for (const auto& f : one_packet(scene, config, unit)) n += f.ret.distance_m > 0.0;
    return n;
  };
  EXPECT_EQ(count_returns(Scene({facing_wall(20.0, 0.002)}), on), 0);
  EXPECT_EQ(count_returns(Scene({facing_wall(20.0, 0.002)}), exact_unit_config()), 384);
  EXPECT_EQ(count_returns(Scene({facing_wall(10.0, 0.002)}), on), 384);
  EXPECT_EQ(count_returns(Scene({facing_wall(20.0, 0.5)}), on), 384);
}

TEST(LidarMaterials, GlassLetsTheBeamThroughAndAMirrorReturnsOnlyHeadOn) {
  const LidarUnit unit = make_lidar_unit(3, exact_unit_config());
  const auto glass = one_packet(Scene({facing_wall(4.0, 0.5, Material::Glass), facing_wall(9.0, 0.5)}), exact_unit_config(), unit);
  for (const auto& f : glass) {
    EXPECT_GT(f.ret.distance_m, 8.9);  // the wall behind (from the optical centre), never the pane
    EXPECT_LT(f.ret.distance_m, 9.0 / std::cos(16.0 * kDegToRad));
  }
  int head_on = 0, lost = 0;
  for (const auto& f : one_packet(Scene({facing_wall(5.0, 0.5, Material::Specular)}), exact_unit_config(), unit)) {
    if (f.ret.distance_m == 0.0) {
      ++lost;
      continue;
    }
    ++head_on;
    // Within 2 deg of the normal: the wall is 5 m away along it.
    EXPECT_LT(f.ret.distance_m, 5.0 / std::cos(2.0 * kDegToRad) + 1e-9);
  }
  EXPECT_GT(head_on, 0);  // the +-1 deg lasers near azimuth 0
  EXPECT_GT(lost, 300);   // the other lasers: reflected away
}

TEST(LidarCageBars, OccludeWithinMinRangeAndReturnBeyond) {
  const LidarUnit unit = make_lidar_unit(3, exact_unit_config());
  const Scene scene({facing_wall(8.0, 0.5)});
  LidarConfig small = exact_unit_config();
  small.cage_bars.enabled = true;  // the bench's cage: bars 0.3 m out, inside min range
  LidarConfig large = small;
  large.cage_bars.cage_radius_m = 1.0;
  large.cage_bars.bar_radius_m = 0.05;
  int lost = 0, bar_returns = 0, wall_returns = 0;
  for (const auto& f : one_packet(scene, small, unit)) lost += f.ret.distance_m == 0.0;
  for (const auto& f : one_packet(scene, large, unit)) {
    if (f.ret.distance_m > 0.9 && f.ret.distance_m < 1.1) ++bar_returns;
    if (f.ret.distance_m > 7.9) ++wall_returns;
  }
  // Bars parallel to y at 0, 45, ... deg about it: the one on +x (elevation 0)
  // and the ones at +-45 deg are out of the lasers' +-15 deg, the one at 0 deg
  // shades the lasers within +-atan(r_bar / R) of the horizon.
  EXPECT_GT(lost, 0);
  EXPECT_GT(bar_returns, 0);
  EXPECT_GT(wall_returns, 0);
  for (const auto& f : one_packet(scene, exact_unit_config(), unit)) EXPECT_GT(f.ret.distance_m, 7.9);
}

TEST(SceneMaterial, IsReadAndCheckedByName) {
  const YAML::Node ok = YAML::Load(
      "objects:\n  - {type: box, material: glass, center_m: [0, 0, 0], size_m: [1, 1, 1]}\n"
      "  - {type: plane, center_m: [0, 0, 0]}\n");
  const Scene scene = parse_scene(ok, "s.yaml");
  EXPECT_EQ(scene.primitives()[0].material, Material::Glass);
  EXPECT_EQ(scene.primitives()[1].material, Material::Diffuse);
  const YAML::Node bad = YAML::Load("objects:\n  - {type: plane, material: metal, center_m: [0, 0, 0]}\n");
  try {
    parse_scene(bad, "s.yaml");
    FAIL() << "accepted material: metal";
  } catch (const SimConfigError& e) {
    EXPECT_STREQ(e.what(), "s.yaml: objects[0].material: must be diffuse, specular or glass, got 'metal'");
  }
}

}  // namespace
}  // namespace tumble::sim
