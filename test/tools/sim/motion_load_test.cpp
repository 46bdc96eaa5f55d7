// Motion YAML: the shipped bench motions load, are exact, and reach but never
// exceed the paper's envelope (3.5 m/s, 200 m/s^2, 11 rad/s, 800 rad/s^2);
// bad motions are refused with the key path and the reason.
#include "test/tools/sim/motion_checks.hpp"
#include "tools/sim/motion_load.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace tumble::sim {
namespace {

std::string motion_file(const std::string& name) {
  return (std::filesystem::path(TUMBLE_SIM_SCENES_DIR).parent_path() / "motions" / name).string();
}

std::string motion_error_of(const std::string& yaml) {
  try {
    MotionLoadOptions o;
    o.source_name = "bad.yaml";
    load_motion(YAML::Load(yaml), o);
  } catch (const SimConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

constexpr double kExact = 1e-9;  // peaks are reached analytically; sampling finds them to ~1e-6 relative

TEST(MotionLoad, RailReachesTopSpeedAndTheEndStopShock) {
  const auto rail = load_motion_file(motion_file("rail.yaml"));
  const test::Peaks p = test::sweep_peaks(*rail, 4e-3);  // shortest pulse: the 13 ms end-stop shock
  EXPECT_NEAR(p.speed_m_s, 3.5, 1e-9);
  EXPECT_LE(p.speed_m_s, 3.5 + kExact);
  EXPECT_NEAR(p.accel_m_s2, 200.0, 1e-3);
  EXPECT_LE(p.accel_m_s2, 200.0 + kExact);
  EXPECT_EQ(p.rate_rad_s, 0.0);
  EXPECT_LT(rail->at(0).v_w.norm() + rail->at(rail->duration_s()).v_w.norm(), 1e-12) << "starts and ends at rest";
  test::expect_derivatives(*rail, 200);
}

TEST(MotionLoad, TurntableReachesElevenRadPerSecondAndEightHundred) {
  const auto table = load_motion_file(motion_file("turntable.yaml"));
  const test::Peaks p = test::sweep_peaks(*table, 2e-3);  // shortest bump: each 2.5 ms half of the 5 ms jolt
  EXPECT_NEAR(p.rate_rad_s, 11.0, 1e-6);
  EXPECT_LE(p.rate_rad_s, 11.0 + kExact);
  EXPECT_NEAR(p.angular_accel_rad_s2, 800.0, 1e-3);
  EXPECT_LE(p.angular_accel_rad_s2, 800.0 + kExact);
  EXPECT_LE(p.accel_m_s2, 200.0);
  EXPECT_LE(p.speed_m_s, 3.5);
  test::DerivativeTolerance tol;
  tol.a_m_s2 = 2e-3;
  test::expect_derivatives(*table, 200, {}, tol);
}

TEST(MotionLoad, RollingCageStaysInsideThePaperEnvelope) {
  const auto cage = load_motion_file(motion_file("rolling_cage.yaml"));
  const test::Peaks p = test::sweep_peaks(*cage, 1e-3);  // shortest bump: half of a 4 * 0.3 / 800 = 1.5 ms jolt
  EXPECT_LE(p.speed_m_s, 3.5);
  EXPECT_LE(p.accel_m_s2, 200.0 + kExact);
  EXPECT_LE(p.rate_rad_s, 11.0 + kExact);
  EXPECT_LE(p.angular_accel_rad_s2, 800.0 + kExact);
  // The draws are uniform in the configured ranges: well above their lower ends.
  EXPECT_GT(p.accel_m_s2, 120.0);
  EXPECT_GT(p.angular_accel_rad_s2, 400.0);
  test::DerivativeTolerance tol;
  tol.a_m_s2 = 3e-3;
  tol.alpha_rad_s2 = 5e-3;
  test::expect_derivatives(*cage, 100, {}, tol);
}

TEST(MotionLoad, SeedOverrideChangesTheRunAndIsDeterministic) {
  const auto a = load_motion_file(motion_file("rolling_cage.yaml"), 5);
  const auto b = load_motion_file(motion_file("rolling_cage.yaml"), 5);
  const auto c = load_motion_file(motion_file("rolling_cage.yaml"), 6);
  bool differs = false;
  for (double t = 0; t < a->duration_s(); t += 0.05) {
    EXPECT_TRUE(a->at(t).T_wb.isApprox(b->at(t).T_wb, 0)) << "t=" << t;
    differs = differs || !a->at(t).T_wb.isApprox(c->at(t).T_wb, 1e-9);
  }
  EXPECT_TRUE(differs);
}

TEST(MotionLoad, EveryShippedMotionLoadsAndIsConsistent) {
  int loaded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(motion_file(""))) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().filename().string());
    const auto m = load_motion_file(entry.path().string());
    ASSERT_GT(m->duration_s(), 0.0);
    test::DerivativeTolerance tol;
    tol.a_m_s2 = 3e-3;
    tol.alpha_rad_s2 = 5e-3;
    test::expect_derivatives(*m, 40, {}, tol);
    ++loaded;
  }
  EXPECT_GE(loaded, 5);
}

TEST(MotionLoad, CorridorWalkTurnsAroundAndComesBack) {
  const auto m = load_motion_file(motion_file("corridor_walk.yaml"));
  const MotionState start = m->at(0), end = m->at(m->duration_s());
  EXPECT_LT((end.T_wb.translation() - start.T_wb.translation()).norm(), 1e-9);
  EXPECT_TRUE((end.T_wb.linear() * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitX(), 1e-9));
}

TEST(MotionLoad, KeyPathInsideAnEnclosingFile) {
  MotionLoadOptions o;
  o.source_name = "bench.yaml";
  o.key_path = "runs[2].motion";
  try {
    load_motion(YAML::Load("{type: static}"), o);
    FAIL();
  } catch (const SimConfigError& e) {
    EXPECT_STREQ(e.what(), "bench.yaml: runs[2].motion.duration_s: missing");
  }
}

TEST(MotionLoad, ErrorsNameTheKeyAndWhy) {
  EXPECT_EQ(motion_error_of("{type: teleport}"),
            "bad.yaml: type: must be one of: static, rail, turntable, rolling_cage, walk, vibration, sequence, "
            "superpose (got 'teleport')");
  EXPECT_EQ(motion_error_of("{type: static, duration_s: -1}"), "bad.yaml: duration_s: must be a positive number");
  EXPECT_EQ(motion_error_of("{type: rail, profile: [{hold_s: 1}, {ramp: {to_m_s: 3, peak_m_s2: 0}}]}"),
            "bad.yaml: profile[1].ramp.peak_m_s2: must be a positive number");
  EXPECT_EQ(motion_error_of("{type: rail, profile: [{ramp: {to_rad_s: 3, peak_m_s2: 2}}]}"),
            "bad.yaml: profile[0].ramp.to_rad_s: unknown key (allowed: to_m_s peak_m_s2 rise_s)");
  EXPECT_EQ(motion_error_of("{type: rail, profile: [{ramp: {to_m_s: 1, peak_m_s2: 2, rise_s: 0.6}}]}"),
            "bad.yaml: profile[0].ramp.rise_s: too long for this change: at most 0.5 s (|change| / peak_m_s2)");
  EXPECT_EQ(motion_error_of("{type: rail, profile: [{shock: {peak_m_s2: 200, restitution: 0.5}}]}"),
            "bad.yaml: profile[0].shock: an end-stop shock (restitution) needs a nonzero velocity before it");
  EXPECT_EQ(motion_error_of("{type: rail, profile: [{ramp: {to_m_s: 1, peak_m_s2: 2}}, {travel: {distance_m: 3, max_m_s: 1, "
                     "peak_m_s2: 1}}]}"),
            "bad.yaml: profile[1].travel: must start at rest (add a ramp to 0 before it)");
  EXPECT_EQ(motion_error_of("{type: rail, profile: [{fly: 2}]}"),
            "bad.yaml: profile[0]: unknown step 'fly' (allowed: hold_s, ramp, travel, shock, jolt)");
  EXPECT_EQ(motion_error_of("{type: turntable, profile: []}"), "bad.yaml: profile: must be a non-empty list of steps");
  EXPECT_EQ(motion_error_of("{type: rolling_cage, radius_m: 0.25, roll: [{hold_s: 1}], bounces: {count: 1, peak_m_s2: [5, 8]}}"),
            "bad.yaml: bounces.peak_m_s2: must exceed g = 9.80665 m/s^2 (an impact has to lift the cage)");
  EXPECT_EQ(motion_error_of("{type: rolling_cage, radius_m: 0.25, roll: [{hold_s: 1}], bounces: {count: 1, height_m: [0.2, "
                     "0.1]}}"),
            "bad.yaml: bounces.height_m: must be [min, max] with 0 < min <= max, or one positive number");
  EXPECT_EQ(motion_error_of("{type: rolling_cage, radius_m: 0.25, roll: [{ramp: {to_rad_s: 5, peak_rad_s2: 20}}, {hold_s: 1}], "
                     "jolts: {count: 50}}"),
            "bad.yaml: jolts.count: too many events: they do not fit, with min_gap_s between them, in the parts of "
            "the roll at a constant nonzero rate");
  EXPECT_EQ(motion_error_of("{type: rolling_cage, radius_m: 0.25, roll: [{hold_s: 1}], seed: -3}"),
            "bad.yaml: seed: must be an unsigned integer");
  EXPECT_EQ(motion_error_of("{type: sequence, parts: [{type: static, duration_s: 1}, {type: rail, profile: [{hold_s: 1}], "
                     "origin: {xyz_m: [1, 0, 0]}}]}"),
            "bad.yaml: parts[1].origin: only the first part can be placed; later parts continue from the previous one");
  EXPECT_EQ(motion_error_of("{type: sequence, parts: [{type: rail, profile: [{ramp: {to_m_s: 1, peak_m_s2: 2}}]}, "
                     "{type: static, duration_s: 1}]}"),
            "bad.yaml: parts: part 1 does not continue part 0: velocity jumps from [1 0 0] to [0 0 0] m/s");
  EXPECT_EQ(motion_error_of("{type: vibration, duration_s: 1, frequency_hz: 10, fade_s: 0.8}"),
            "bad.yaml: fade_s: must be at most duration_s / 2");
  EXPECT_EQ(motion_error_of("{type: superpose, base: {type: static, duration_s: 1}}"), "bad.yaml: offset: missing");
  EXPECT_EQ(motion_error_of("{type: walk, forward: [{hold_s: 1}], origin: {xyz: [0, 0, 0]}}"),
            "bad.yaml: origin.xyz: unknown key (allowed: xyz_m rpy_deg)");
  EXPECT_EQ(motion_error_of("[1, 2]"), "bad.yaml: (top level): must be a map of key: value");
}

}  // namespace
}  // namespace tumble::sim
