// Moving people (people.*): a beam meets a walker where the walker is at its
// firing time, the rope puller stays ahead of the robot, and people change
// nothing but the returns they stand in front of.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <vector>

#include "test/tools/sim/sensor_test_support.hpp"
#include "drivers/rs16/msop_decode.hpp"
#include "tools/sim/lidar_model.hpp"
#include "tools/sim/motion_load.hpp"
#include "tools/sim/people.hpp"
#include "tools/sim/scenario.hpp"
#include "tools/sim/sim_run.hpp"

namespace tumble::sim {
namespace {

using test::SpinMotion;
using test::TempDir;

// A wall x = 20 m behind everything, facing the lidar at the origin.
Scene wall_at_20m() {
  Primitive p;
  p.shape = Shape::Plane;
  p.pose_w = Eigen::Translation3d(20.0, 0, 0) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY());
  return Scene({p});
}

LidarConfig noiseless_lidar() {
  LidarConfig c;
  c.range_noise_m = 0.0;
  c.dropout_probability = 0.0;
  return c;
}

// One walker crossing x = 5 m from y = -3 to 3 at 1.2 m/s: at y = 0 at t = 2.5 s.
PeopleConfig one_walker() {
  PeopleConfig c;
  c.walkers = true;
  WalkerPath w;
  w.from_m = {5.0, -3.0};
  w.to_m = {5.0, 3.0};
  w.speed_m_s = 1.2;
  c.walker_paths.push_back(w);
  return c;
}

// Range along a beam to a vertical cylinder of radius r about (cx, cy), by
// the horizontal line-circle intersection (the beam's slope only stretches it).
double range_to_cylinder(const Beam& beam, Eigen::Vector2d centre, double radius) {
  const Eigen::Vector2d o = beam.origin_l.head<2>();
  const Eigen::Vector2d d = beam.direction_l.head<2>();
  const Eigen::Vector2d oc = o - centre;
  const double a = d.squaredNorm(), b = oc.dot(d), c = oc.squaredNorm() - radius * radius;
  const double disc = b * b - a * c;
  return disc < 0 ? -1.0 : (-b - std::sqrt(disc)) / a;
}

TEST(People, ABeamAimedAtAWalkerHitsItAtItsPositionAtTheFiringTime) {
  const SpinMotion still({0, 0, 1.0}, 0.0, 10.0);
  const Scene scene = wall_at_20m();
  const People people(one_walker(), still, 10.0, 1);
  EXPECT_NEAR((people.position_xy(0, 2.5) - Eigen::Vector2d(5.0, 0.0)).norm(), 0.0, 1e-12);
  const LidarUnit unit = make_lidar_unit(1, noiseless_lidar());
  // The motor points at 357.6 deg at t = 2.5 s (25 turns later): the packet spans 357.6..2.4 deg.
  LidarModel model(noiseless_lidar(), unit, scene, still, 1, 357.6, &people);
  int person_returns = 0;
  for (const std::int64_t first_ns : {std::int64_t{0}, std::int64_t{2'500'000'000}}) {
    rs16::MsopPacketData packet;
    model.fill_packet(first_ns, packet);
    const auto blocks = block_azimuths_centideg(357.6, 3600.0, first_ns);
    for (int b = 0; b < 12; ++b) {
      for (int c = 0; c < 32; ++c) {
        const auto& ret = packet.blocks[static_cast<std::size_t>(b)].channels[static_cast<std::size_t>(c)];
        const std::int64_t t_ns = first_ns + b * kRs16BlockPeriodNs + (c / 16) * kRs16SequencePeriodNs +
                                  (c % 16) * kRs16LaserSpacingNs;
        const double vertical_deg = unit.vertical_angles_deg[static_cast<std::size_t>(c % 16)];
        const Beam beam = rs16_beam(channel_azimuth_deg(blocks, b, c, 600), vertical_deg);
        const double t_s = static_cast<double>(t_ns) * 1e-9;
        const double to_person_m = range_to_cylinder(beam, people.position_xy(0, t_s), 0.25);
        const double z_at_person_m = 1.0 + to_person_m * beam.direction_l.z();
        const bool on_person = to_person_m > 0 && z_at_person_m >= 0.0 && z_at_person_m <= 1.75;
        if (on_person) {
          ++person_returns;
          EXPECT_NEAR(ret.distance_m, to_person_m, 1e-6) << "block " << b << " channel " << c;
          EXPECT_LE(ret.reflectivity, 40);  // 0.4 clothing, times cos(incidence) on the round body
          EXPECT_GE(ret.reflectivity, 1);
        } else {
          EXPECT_NEAR(ret.distance_m, (20.0 - beam.origin_l.x()) / beam.direction_l.x(), 1e-6);
        }
      }
    }
    // At t = 0 the walker is 3 m to the side: the beam sees the wall.
    if (first_ns == 0) {
      EXPECT_EQ(person_returns, 0);
    }
  }
  EXPECT_GT(person_returns, 100);
}

std::unique_ptr<Motion> cage_out_and_back() {
  return load_motion(YAML::Load(R"(
type: rolling_cage
radius_m: 0.3
mount: {xyz_m: [0, 0, 0.05]}
origin: {rpy_deg: [0, 0, 30]}
roll:
  - hold_s: 1.5
  - ramp: {to_rad_s: 10, peak_rad_s2: 20}
  - hold_s: 3
  - ramp: {to_rad_s: -8, peak_rad_s2: 20}
  - hold_s: 3
  - ramp: {to_rad_s: 0, peak_rad_s2: 20}
  - hold_s: 1
seed: 4
bounces: {count: 2}
jolts: {count: 3}
)"));
}

TEST(People, TheRopePullerWalksOnePointFiveToTwoPointFiveMetresAheadOfTheRobot) {
  const auto robot = cage_out_and_back();
  PeopleConfig config;
  config.rope_puller = true;
  const People people(config, *robot, robot->duration_s(), 3);
  ASSERT_EQ(people.count(), 1u);
  int ahead_checks = 0;
  for (double t = 0.0; t <= robot->duration_s(); t += 0.005) {
    const MotionState s = robot->at(t);
    const Eigen::Vector2d to_puller = people.position_xy(0, t) - s.T_wb.translation().head<2>();
    EXPECT_GE(to_puller.norm(), 1.5) << "t = " << t;
    EXPECT_LE(to_puller.norm(), 2.5) << "t = " << t;
    // While rolling steadily one way the puller is in front, within ~15 deg.
    const bool steady_out = t > 3.5 && t < 5.0, steady_back = t > 8.5 && t < 9.5;
    if (steady_out || steady_back) {
      const Eigen::Vector2d v = s.v_w.head<2>();
      EXPECT_GT(to_puller.normalized().dot(v.normalized()), std::cos(15.0 * M_PI / 180.0)) << "t = " << t;
      ++ahead_checks;
    }
  }
  EXPECT_GT(ahead_checks, 300);
  // Before the pull the puller already stands where the cage will go (+x turned 30 deg).
  const Eigen::Vector2d at_start = people.position_xy(0, 0.0) - robot->at(0.0).T_wb.translation().head<2>();
  EXPECT_GT(at_start.normalized().dot(Eigen::Vector2d(std::cos(M_PI / 6), std::sin(M_PI / 6))), 0.99);
}

TEST(People, DrawnWalkersCrossTheRobotsRouteButKeepOffTheRobot) {
  const auto robot = cage_out_and_back();
  PeopleConfig config;
  config.walkers = true;
  config.walker_count = 8;
  const People people(config, *robot, robot->duration_s(), 11);
  ASSERT_EQ(people.count(), 8u);
  for (std::size_t i = 0; i < people.count(); ++i) {
    const WalkerPath& w = people.walkers()[i];
    const double length = (w.to_m - w.from_m).norm();
    EXPECT_GE(length, 8.0);
    EXPECT_LE(length, 16.0);
    EXPECT_GE(w.speed_m_s, 1.0);
    EXPECT_LE(w.speed_m_s, 1.5);
    double closest_to_robot = 1e9, route_to_path = 1e9;
    for (double t = 0.0; t <= robot->duration_s(); t += 0.005) {
      const Eigen::Vector2d robot_xy = robot->at(t).T_wb.translation().head<2>();
      closest_to_robot = std::min(closest_to_robot, (people.position_xy(i, t) - robot_xy).norm());
      // Distance from the robot's position to the walker's path segment.
      const double along = std::clamp((robot_xy - w.from_m).dot(w.to_m - w.from_m) / (length * length), 0.0, 1.0);
      route_to_path = std::min(route_to_path, (w.from_m + along * (w.to_m - w.from_m) - robot_xy).norm());
    }
    // Sampled at 20 Hz when drawn: at a closing speed of up to 5 m/s they may come a little nearer in between.
    EXPECT_GE(closest_to_robot, 0.8) << "walker " << i;
    EXPECT_LT(route_to_path, 1e-3) << "walker " << i;
  }
}

TEST(People, SomeoneOutOfSightChangesNoByteOfTheLidarStream) {
  const auto robot = cage_out_and_back();
  PeopleConfig config;
  config.walkers = true;
  WalkerPath far_away;
  far_away.from_m = {1000.0, 0.0};
  far_away.to_m = {1000.0, 10.0};
  config.walker_paths.push_back(far_away);
  const People people(config, *robot, robot->duration_s(), 1);
  const Scene scene = wall_at_20m();
  const LidarUnit unit = make_lidar_unit(2, LidarConfig{});
  LidarModel today(LidarConfig{}, unit, scene, *robot, 9, 12.0);
  LidarModel with_people(LidarConfig{}, unit, scene, *robot, 9, 12.0, &people);
  for (std::int64_t t_ns = 0; t_ns < 6'000'000'000; t_ns += 50 * kRs16PacketPeriodNs) {
    rs16::MsopPacketData a, b;
    a.utc_time_ns = b.utc_time_ns = 1'622'030'400'000'000'000 + t_ns;
    today.fill_packet(t_ns, a);
    with_people.fill_packet(t_ns, b);
    EXPECT_EQ(rs16::encode_msop(a), rs16::encode_msop(b)) << "packet at " << t_ns << " ns";
  }
}

// A box room, a static lidar; walkers and the puller in the same-seed run.
std::string room_scenario(const std::filesystem::path& dir, bool people) {
  const auto scene = test::BoxRoom{}.write(dir);
  std::string text = test::box_room_scenario_yaml(scene, 1.0);
  if (people) text += "people:\n  walkers: {count: 2, path_length_m: [4, 6]}\n  rope_puller: {}\n";
  return text;
}

TEST(People, ASameSeedPairDiffersOnlyInTheReturnsAPersonStandsIn) {
  TempDir dir("people_pair");
  const SimRun without(parse_scenario(YAML::Load(room_scenario(dir.path(), false)), "a.yaml", dir.path()));
  const SimRun with(parse_scenario(YAML::Load(room_scenario(dir.path(), true)), "b.yaml", dir.path()));
  ASSERT_EQ(with.people().count(), 3u);

  ImuStream imu_a = without.imu_stream(), imu_b = with.imu_stream();
  SerialRead read_a, read_b;
  int imu_reads = 0;
  while (imu_a.next(read_a)) {
    ASSERT_TRUE(imu_b.next(read_b));
    ASSERT_EQ(read_a.arrival_ns, read_b.arrival_ns);
    ASSERT_EQ(read_a.bytes, read_b.bytes);
    ++imu_reads;
  }
  EXPECT_FALSE(imu_b.next(read_b));
  EXPECT_GT(imu_reads, 10);

  LidarStream lidar_a = without.lidar_stream(), lidar_b = with.lidar_stream();
  LidarDatagram da, db;
  std::size_t returns = 0, nearer = 0, other_changes = 0;
  while (lidar_a.next(da)) {
    ASSERT_TRUE(lidar_b.next(db));
    ASSERT_EQ(da.arrival_ns, db.arrival_ns);
    if (da.is_difop) {
      EXPECT_EQ(da.payload, db.payload);
      continue;
    }
    rs16::MsopPacketData pa, pb;
    rs16::MsopHeader ha, hb;
    ASSERT_EQ(rs16::decode_msop_fields(da.payload, 0.005, pa, ha), rs16::PacketError::None);
    ASSERT_EQ(rs16::decode_msop_fields(db.payload, 0.005, pb, hb), rs16::PacketError::None);
    for (std::size_t b = 0; b < 12; ++b) {
      for (std::size_t c = 0; c < 32; ++c) {
        const auto& ra = pa.blocks[b].channels[c];
        const auto& rb = pb.blocks[b].channels[c];
        ++returns;
        if (ra.distance_m == rb.distance_m && ra.reflectivity == rb.reflectivity) continue;
        // A person stands in front of the wall: nearer, or a return where the wall gave none.
        if (rb.distance_m > 0 && (ra.distance_m == 0 || rb.distance_m < ra.distance_m)) {
          ++nearer;
        } else if (rb.distance_m == 0 && ra.distance_m > 0) {
          ++nearer;  // a person inside min range, or noise carried past it
        } else {
          ++other_changes;
        }
      }
    }
  }
  EXPECT_FALSE(lidar_b.next(db));
  EXPECT_EQ(other_changes, 0u);
  EXPECT_GT(nearer, returns / 100);  // the puller alone fills ~4 % of the view
  EXPECT_LT(nearer, returns / 3);
}

TEST(People, ScenarioKeysAreCheckedAndOffByDefault) {
  const auto error_of = [](const std::string& people) {
    try {
      parse_scenario(YAML::Load("scene: garage\nmotion: static\npeople:\n" + people), "s.yaml", ".");
    } catch (const SimConfigError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const Scenario plain = parse_scenario(YAML::Load("scene: garage\nmotion: static\n"), "s.yaml", ".");
  EXPECT_FALSE(plain.people.walkers);
  EXPECT_FALSE(plain.people.rope_puller);
  EXPECT_FALSE(scenario_to_yaml(plain)["people"]);
  EXPECT_NE(error_of("  walkers: {cout: 3}\n").find("s.yaml: people.walkers.cout: unknown key"), std::string::npos)
      << error_of("  walkers: {cout: 3}\n");
  EXPECT_NE(error_of("  walkers: {count: 2, paths: [{from_m: [0, 0], to_m: [1, 1]}]}\n").find("not both"),
            std::string::npos);
  EXPECT_NE(error_of("  walkers: {paths: [{from_m: [0, 0, 1], to_m: [1, 1]}]}\n").find("people.walkers.paths[0].from_m"),
            std::string::npos);
  EXPECT_NE(error_of("  rope_puller: {ahead_m: 0.1}\n").find("people.rope_puller.ahead_m: must be in"),
            std::string::npos);
  EXPECT_EQ(error_of("  rope_puller: {}\n  walkers: {paths: [{from_m: [0, 0], to_m: [1, 1], speed_m_s: 1.1}]}\n"),
            "(no error)");
  // Round trip: what the manifest and bench files carry reads back the same.
  const Scenario s = parse_scenario(
      YAML::Load("scene: garage\nmotion: static\npeople: {seed: 4, rope_puller: {ahead_m: 2.2}, walkers: {count: 5}}\n"),
      "s.yaml", ".");
  const Scenario back = parse_scenario(scenario_to_yaml(s), "back.yaml", ".");
  EXPECT_EQ(back.people.seed, std::optional<std::uint64_t>(4));
  EXPECT_TRUE(back.people.rope_puller);
  EXPECT_EQ(back.people.puller_ahead_m, 2.2);
  EXPECT_EQ(back.people.walker_count, 5);
}

}  // namespace
}  // namespace tumble::sim
