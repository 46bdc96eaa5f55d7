// Every motion type: reported velocity, acceleration, angular velocity and
// angular acceleration agree with central differences of the pose; sequences
// join continuously; superposition composes exactly.
#include "test/tools/sim/motion_checks.hpp"
#include "tools/sim/motion_compose.hpp"
#include "tools/sim/motion_primitives.hpp"
#include "tools/sim/motion_walk.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace tumble::sim {
namespace {

using test::expect_derivatives;

ScalarProfile spin_profile() {
  ScalarProfile p;
  p.hold(0.2);
  p.change_velocity(10.0, 40.0, 0.1);
  p.hold(0.3);
  p.jolt(800.0, 0.005);
  p.hold(0.2);
  p.shock(800.0, -10.0);
  p.hold(0.2);
  return p;
}

// Times inside the fast events of spin_profile(), where derivatives are largest.
std::vector<double> spin_event_times(const ScalarProfile& p) {
  std::vector<double> times;
  for (const auto& seg : p.segments())
    if (seg.duration < 0.02)
      for (double f : {0.1, 0.37, 0.5, 0.81}) times.push_back(seg.t0 + f * seg.duration);
  return times;
}

TEST(Motion, ComposeMatchesDifferencesForTwoSpinningFrames) {
  // Parent spinning about a tilted axis and translating; child spinning about another axis, off-centre.
  class Nested final : public Motion {
   public:
    MotionState at(double t) const override {
      MotionState parent = rotation_state(Eigen::Vector3d(1, 2, 3).normalized(), {1.3 * t * t, 2.6 * t, 2.6, 0});
      parent.T_wb.translation() = Eigen::Vector3d(t, 0.5 * t * t, std::sin(t));
      parent.v_w = Eigen::Vector3d(1, t, std::cos(t));
      parent.a_w = Eigen::Vector3d(0, 1, -std::sin(t));
      MotionState child = rotation_state(Eigen::Vector3d(0, 1, -1).normalized(), {std::sin(3 * t), 3 * std::cos(3 * t), -9 * std::sin(3 * t), 0});
      child.T_wb.translation() = Eigen::Vector3d(0.3, -0.2, 0.1 * t);
      child.v_w = Eigen::Vector3d(0, 0, 0.1);
      return compose(parent, child);
    }
    double duration_s() const override { return 3.0; }
  };
  expect_derivatives(Nested(), 50);
}

TEST(Motion, PoseFromRpyIsZYX) {
  const Eigen::Isometry3d T = pose_from_xyz_rpy_deg({1, 2, 3}, {0, 0, 90});
  EXPECT_TRUE((T.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  const Eigen::Isometry3d P = pose_from_xyz_rpy_deg({0, 0, 0}, {0, 90, 0});
  EXPECT_TRUE((P.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
}

TEST(Motion, RailDerivativesIncludingTheEndStopShock) {
  ScalarProfile p;
  p.hold(0.5);
  p.change_velocity(3.5, 4.0, 0.3);
  p.hold(1.0);
  p.shock(200.0, -3.5 * 1.3);
  p.change_velocity(0.0, 2.0);
  const double shock_start = 0.5 + 3.5 / 4.0 + 0.3 + 1.0;
  const RailMotion rail(Eigen::Vector3d(1, 1, 0), p, pose_from_xyz_rpy_deg({0, 0, 1}, {10, 0, 30}));
  expect_derivatives(rail, 100, {shock_start + 0.003, shock_start + 0.0113, shock_start + 0.02});
  const MotionState cruise = rail.at(2.0);
  EXPECT_NEAR(cruise.v_w.norm(), 3.5, 1e-12);
  EXPECT_TRUE(cruise.v_w.normalized().isApprox(Eigen::Vector3d(1, 1, 0).normalized(), 1e-12));
  EXPECT_EQ(cruise.omega_b, Eigen::Vector3d::Zero());
}

TEST(Motion, TurntableOffAxisMountSeesCentripetalAndTangentialAcceleration) {
  const ScalarProfile p = spin_profile();
  const TurntableMotion table(Eigen::Vector3d::UnitZ(), p, pose_from_xyz_rpy_deg({0.15, 0, 0.25}, {0, 30, 0}));
  test::DerivativeTolerance tol;
  tol.a_m_s2 = 2e-3;
  expect_derivatives(table, 100, spin_event_times(p), tol);
  // At constant rate: |a| = w^2 r, |v| = w r, |omega| = w.
  const MotionState s = table.at(0.2 + 10.0 / 40.0 + 0.1 + 0.15);
  EXPECT_NEAR(s.omega_b.norm(), 10.0, 1e-12);
  EXPECT_NEAR(s.v_w.norm(), 10.0 * 0.15, 1e-12);
  EXPECT_NEAR(s.a_w.norm(), 100.0 * 0.15, 1e-9);
  EXPECT_NEAR(s.alpha_b.norm(), 0.0, 1e-12);
  EXPECT_NEAR(s.T_wb.translation().z(), 0.25, 1e-12);
}

TEST(Motion, WalkDerivativesAndGaitFadesWithSpeed) {
  WalkParams w;
  w.forward_m.hold(0.5);
  w.forward_m.travel(6.0, 1.4, 0.8);
  w.forward_m.hold(0.5);
  w.mount = pose_from_xyz_rpy_deg({0.1, 0, 0.2}, {0, -10, 0});
  const WalkMotion walk(w);
  expect_derivatives(walk, 200);
  // At rest at both ends: no bob, no sway, nothing moving.
  for (double t : {0.2, walk.duration_s() - 0.2}) {
    const MotionState s = walk.at(t);
    EXPECT_NEAR(s.v_w.norm(), 0.0, 1e-12);
    EXPECT_NEAR(s.omega_b.norm(), 0.0, 1e-12);
  }
  EXPECT_TRUE(walk.at(walk.duration_s()).T_wb.translation().isApprox(Eigen::Vector3d(6.1, 0, 0.2), 1e-9));
}

TEST(Motion, VibrationDerivativesAndFade) {
  VibrationParams v;
  v.duration_s = 2.0;
  v.frequency_hz = 35;
  v.translation_m = {0.001, 0.002, 0.003};
  v.rotation_rad = {0.004, 0.002, 0.001};
  v.fade_s = 0.4;
  const VibrationMotion vib(v);
  expect_derivatives(vib, 300);
  EXPECT_TRUE(vib.at(0).T_wb.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(vib.at(2.0).T_wb.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_NEAR(vib.at(0).v_w.norm() + vib.at(2.0).v_w.norm(), 0.0, 1e-15);
}

TEST(Motion, SequenceContinuesFromThePreviousEnd) {
  ScalarProfile rail_profile;
  rail_profile.travel(5.0, 2.0, 3.0);
  ScalarProfile turn;
  turn.travel(std::numbers::pi / 2, 1.5, 3.0);
  std::vector<std::unique_ptr<Motion>> parts;
  parts.push_back(std::make_unique<RailMotion>(Eigen::Vector3d::UnitX(), rail_profile));
  parts.push_back(std::make_unique<TurntableMotion>(Eigen::Vector3d::UnitZ(), turn));
  parts.push_back(std::make_unique<RailMotion>(Eigen::Vector3d::UnitX(), rail_profile));
  const SequenceMotion seq(std::move(parts));
  const double d_rail = rail_profile.end_s(), d_turn = turn.end_s();
  EXPECT_NEAR(seq.duration_s(), 2 * d_rail + d_turn, 1e-12);
  // Drove 5 m along x, turned left, drove 5 m along the new x = world y.
  const MotionState end = seq.at(seq.duration_s());
  EXPECT_TRUE(end.T_wb.translation().isApprox(Eigen::Vector3d(5, 5, 0), 1e-9)) << end.T_wb.translation().transpose();
  EXPECT_TRUE((end.T_wb.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-9));
  expect_derivatives(seq, 200, {d_rail - 1e-3, d_rail + 1e-3, d_rail + d_turn + 1e-3});
}

TEST(Motion, SequenceRefusesAVelocityJump) {
  std::vector<std::unique_ptr<Motion>> parts;
  parts.push_back(std::make_unique<StaticMotion>(1.0));
  parts.push_back(std::make_unique<RailMotion>(Eigen::Vector3d::UnitX(), ScalarProfile(0, 2.0)));
  try {
    SequenceMotion seq(std::move(parts));
    FAIL() << "a part starting at 2 m/s after a static part must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("part 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("velocity"), std::string::npos) << e.what();
  }
}

TEST(Motion, SuperposedVibrationOnASpinningTable) {
  VibrationParams v;
  v.duration_s = 1.5;
  v.frequency_hz = 20;
  v.translation_m = {0.002, 0.0, 0.001};
  v.rotation_rad = {0.01, 0.0, 0.02};
  v.fade_s = 0.3;
  const ScalarProfile p = spin_profile();
  SuperposedMotion m(std::make_unique<TurntableMotion>(Eigen::Vector3d::UnitZ(), p,
                                                       pose_from_xyz_rpy_deg({0.2, 0, 0}, {0, 0, 0})),
                     std::make_unique<VibrationMotion>(v));
  test::DerivativeTolerance tol;
  tol.a_m_s2 = 2e-3;
  expect_derivatives(m, 200, spin_event_times(p), tol);
  EXPECT_DOUBLE_EQ(m.duration_s(), p.end_s());
}

TEST(Motion, PlacedAndClampedOutsideTheRun) {
  ScalarProfile p;
  p.travel(2.0, 1.0, 1.0);
  const PlacedMotion placed(pose_from_xyz_rpy_deg({1, 2, 3}, {0, 0, 90}),
                            std::make_unique<RailMotion>(Eigen::Vector3d::UnitX(), p));
  EXPECT_TRUE(placed.at(-1.0).T_wb.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE(placed.at(placed.duration_s() + 5).T_wb.translation().isApprox(Eigen::Vector3d(1, 4, 3), 1e-12));
  expect_derivatives(placed, 50);
}

}  // namespace
}  // namespace tumble::sim
