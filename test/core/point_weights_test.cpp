// Weight models against analytic cases: the paper's toy square room (a wall
// parallel to the velocity error is certain under GVTW, not under VTW), TW's
// linear growth, the 16-pair definition of VTW, SAW's formula, GVTW's guards
// and its corner term.
#include "core/point_weights.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "core/rotation.hpp"

namespace tumble {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Constant world velocity and body rate from t = 0, sampled at 100 Hz.
Trajectory constant_motion(const Eigen::Vector3d& v_w, const Eigen::Vector3d& omega_l) {
  Trajectory trajectory(64, SpeedUncertaintyParams{});
  for (int i = 0; i <= 20; ++i) {
    TrajectorySample s;
    s.t_s = 0.01 * i;
    s.q_wl = integrate_body_rate(Eigen::Quaterniond::Identity(), omega_l, s.t_s);
    s.p_w = v_w * s.t_s;
    s.v_w = v_w;
    s.omega_l = omega_l;
    trajectory.push_back(s);
  }
  return trajectory;
}

struct Outputs {
  explicit Outputs(std::size_t n) : sigma_n(n), sigma_s(n), weights(n) {}
  PointWeightOutput spans() { return {sigma_n, sigma_s, weights}; }
  std::vector<double> sigma_n, sigma_s, weights;
};

TEST(PointWeights, SensorNoiseGrowsWithTheBeamFootprintAboveTwoCentimetres) {
  const PointWeightParams params;
  EXPECT_DOUBLE_EQ(sensor_noise_sigma(5.0, params), 0.02);
  EXPECT_DOUBLE_EQ(sensor_noise_sigma(100.0, params), 0.15);
}

TEST(PointWeights, TimeWeightGrowsLinearlyFromTheScanStart) {
  PointWeightParams params;
  params.model = WeightModel::TW;
  const Trajectory trajectory = constant_motion(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const std::vector<Eigen::Vector3d> points(5, Eigen::Vector3d(3, 4, 0));
  const std::vector<double> times{0.05, 0.06, 0.08, 0.1, 0.15};
  Outputs out(points.size());
  PointWeightWorkspace workspace;
  compute_point_weights(params, trajectory, {points, times, {}, {}, {}, 0.05, true}, out.spans(), workspace);
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR(out.sigma_s[i], 0.25 * (times[i] - 0.05), 1e-15);
    EXPECT_EQ(out.weights[i], 1.0);
  }
}

TEST(PointWeights, VtwSpreadIsTheMaxOverTheSixteenOrderedPairs) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d p(10 * u(rng), 10 * u(rng), 2 * u(rng));
    SkewPerturbation perturbation{Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.1,
                                  Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.2};
    std::vector<Eigen::Vector3d> variants;
    for (const double s : {1.0, -1.0}) {
      for (const double s_prime : {1.0, -1.0}) {
        const Eigen::Vector3d theta = s * perturbation.theta_rad;
        const Eigen::Vector3d rotated = Eigen::AngleAxisd(theta.norm(), theta.normalized()) * p;
        variants.push_back(rotated + s_prime * perturbation.delta_m);
      }
    }
    double brute = 0.0;
    for (const auto& a : variants) {
      for (const auto& b : variants) brute = std::max(brute, (a - b).norm());
    }
    EXPECT_NEAR(vtw_max_spread(p, perturbation), brute, 1e-12);
  }
}

TEST(PointWeights, VtwOfPureTranslationAndPureRotation) {
  // p ± δ: the spread is 2‖δ‖. rot(p, ±θ) about z: the chord 2 r sin θ.
  const Eigen::Vector3d p(3.0, 4.0, 1.0);
  EXPECT_NEAR(vtw_max_spread(p, {Eigen::Vector3d(0.03, 0.04, 0.0), Eigen::Vector3d::Zero()}), 0.1, 1e-15);
  EXPECT_NEAR(vtw_max_spread(p, {Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 0.1)}), 2 * 5.0 * std::sin(0.1),
              1e-12);
}

// The paper's toy example: a square room (walls at x, y = ±5 m), the lidar at
// its centre moving along x, no de-skewing (σ_v = 0.14|v|, so the error δ is
// along x only).
TEST(PointWeights, SquareRoomWallParallelToTheVelocityErrorIsCertainUnderGvtwOnly) {
  const double speed = 2.0;
  const Trajectory trajectory = constant_motion(Eigen::Vector3d(speed, 0, 0), Eigen::Vector3d::Zero());
  const std::vector<Eigen::Vector3d> points{{2.0, 5.0, 0.0}, {5.0, -1.0, 0.0}};  // side wall, front wall
  const std::vector<Eigen::Vector3d> normals{{0, -1, 0}, {-1, 0, 0}};
  const std::vector<double> times{0.08, 0.08};
  const PointWeightInput input{points, times, normals, {}, {}, 0.0, false};
  const double delta_x = 0.14 * speed * 0.08;

  PointWeightParams params;
  PointWeightWorkspace workspace;
  Outputs gvtw(2), vtw(2);
  params.model = WeightModel::GVTW;
  compute_point_weights(params, trajectory, input, gvtw.spans(), workspace);
  params.model = WeightModel::VTW;
  compute_point_weights(params, trajectory, input, vtw.spans(), workspace);

  // Side wall: sliding along it does not change the range: σ_s = 0.
  EXPECT_NEAR(gvtw.sigma_s[0], 0.0, 1e-15);
  // VTW does not know the geometry: c2/2 · 2δ = 2δ for both points.
  EXPECT_NEAR(vtw.sigma_s[0], 2.0 * delta_x, 1e-15);
  EXPECT_NEAR(vtw.sigma_s[1], 2.0 * delta_x, 1e-15);
  // Front wall: the range changes by ±δ/cos(incidence): c3/2 · 2δ/|p̂·n|.
  const double cos_incidence = 5.0 / std::sqrt(26.0);
  EXPECT_NEAR(gvtw.sigma_s[1], 4.0 * delta_x / cos_incidence, 1e-12);
}

TEST(PointWeights, GvtwDistanceIsTheRangeFromTheDisplacedOrigin) {
  // Plane z = −2 seen straight down, origin moved 0.1 m down: range 1.9 m.
  const Eigen::Vector3d p(0, 0, -2), n(0, 0, 1);
  EXPECT_NEAR(gvtw_distance(p, n, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, -0.1), 1e-3), 1.9, 1e-15);
  // Tilting the beam by 0.3 rad lengthens it to 2 / cos 0.3.
  EXPECT_NEAR(gvtw_distance(p, n, Eigen::Vector3d(0.3, 0, 0), Eigen::Vector3d::Zero(), 1e-3), 2.0 / std::cos(0.3),
              1e-12);
}

TEST(PointWeights, GvtwGuardsGrazingBeamsAndUnknownNormals) {
  const SkewPerturbation perturbation{Eigen::Vector3d(0.0, 0.01, 0.0), Eigen::Vector3d::Zero()};
  const Eigen::Vector3d p(5.0, 0.0, 0.0);
  // Beam in the plane y = 0 and the origin moved off it: the range would be
  // ±∞; the clamp |p̂·n| ≥ 1e-3 makes it ±0.01/1e-3.
  EXPECT_DOUBLE_EQ(gvtw_max_spread(p, Eigen::Vector3d(0, 1, 0), perturbation, 1e-3), 20.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(gvtw_max_spread(p, Eigen::Vector3d(nan, nan, nan), perturbation, 1e-3), kInf);
  EXPECT_EQ(gvtw_max_spread(p, Eigen::Vector3d::Zero(), perturbation, 1e-3), kInf);
  EXPECT_EQ(gvtw_max_spread(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 0, 0), perturbation, 1e-3), kInf);
}

TEST(PointWeights, SawIsTheLargerOfTheAngleAndCurvatureParts) {
  EXPECT_DOUBLE_EQ(saw_weight(0.0, 0.0, 0.1), 1.0);                               // cos 0
  EXPECT_DOUBLE_EQ(saw_weight(2 * std::numbers::pi, 0.0, 0.1), 0.25);             // cos(π/2) = 0 < floor
  EXPECT_DOUBLE_EQ(saw_weight(2 * std::numbers::pi, 0.05, 0.1), 0.5);             // c / c_r
  EXPECT_DOUBLE_EQ(saw_weight(std::numbers::pi, 0.0, 0.1), std::cos(std::numbers::pi / 4));
  EXPECT_DOUBLE_EQ(saw_weight(std::numbers::pi, 0.5, 0.1), 1.0);                  // capped at 1
}

TEST(PointWeights, SawScanAngleIsTheFractionOfTheScanSwept) {
  PointWeightParams params;
  params.model = WeightModel::SAW;
  const Trajectory trajectory = constant_motion(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const std::vector<Eigen::Vector3d> points(3, Eigen::Vector3d(1, 0, 0));
  const std::vector<double> times{0.0, 0.05, 0.1};
  const std::vector<double> curvatures{0.0, 0.0, 0.0};
  Outputs out(3);
  PointWeightWorkspace workspace;
  compute_point_weights(params, trajectory, {points, times, {}, curvatures, {}, 0.0, true}, out.spans(), workspace);
  EXPECT_DOUBLE_EQ(out.weights[0], 1.0);
  EXPECT_DOUBLE_EQ(out.weights[1], std::cos(std::numbers::pi / 4));
  EXPECT_DOUBLE_EQ(out.weights[2], 0.25);
  EXPECT_EQ(out.sigma_s[2], 0.0);
}

TEST(PointWeights, NoModelLeavesOnlySensorNoise) {
  PointWeightParams params;
  params.model = WeightModel::NM;
  const Trajectory trajectory = constant_motion(Eigen::Vector3d(3, 0, 0), Eigen::Vector3d(0, 0, 5));
  const std::vector<Eigen::Vector3d> points{{20, 0, 0}};
  const std::vector<double> times{0.1};
  Outputs out(1);
  PointWeightWorkspace workspace;
  compute_point_weights(params, trajectory, {points, times, {}, {}, {}, 0.0, true}, out.spans(), workspace);
  EXPECT_EQ(out.sigma_s[0], 0.0);
  EXPECT_DOUBLE_EQ(out.sigma_n[0], 0.03);
}

TEST(PointWeights, RejectsMissingInputsNamingThem) {
  PointWeightParams params;
  const Trajectory trajectory = constant_motion(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const std::vector<Eigen::Vector3d> points(2, Eigen::Vector3d(1, 0, 0));
  const std::vector<double> times(2, 0.0);
  Outputs out(2);
  PointWeightWorkspace workspace;
  params.model = WeightModel::GVTW;
  try {
    compute_point_weights(params, trajectory, {points, times, {}, {}, {}, 0.0, true}, out.spans(), workspace);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("normals"), std::string::npos) << e.what();
  }
  params.model = WeightModel::SAW;
  EXPECT_THROW(
      compute_point_weights(params, trajectory, {points, times, {}, {}, {}, 0.0, true}, out.spans(), workspace),
      std::invalid_argument);
}

TEST(PointWeights, MapKeepsPointsUpToTheSigmaCut) {
  const PointWeightParams params;
  EXPECT_TRUE(keep_in_map(1.0, params));
  EXPECT_FALSE(keep_in_map(1.01, params));
  EXPECT_FALSE(keep_in_map(kInf, params));
  EXPECT_FALSE(keep_in_map(std::numeric_limits<double>::quiet_NaN(), params));
}

TEST(PointWeights, ModelNamesRoundTrip) {
  for (const WeightModel model :
       {WeightModel::NM, WeightModel::TW, WeightModel::VTW, WeightModel::GVTW, WeightModel::SAW}) {
    EXPECT_EQ(weight_model_from_name(weight_model_name(model)), model);
  }
  EXPECT_FALSE(weight_model_from_name("gvtw").has_value());
}

// One ring of a square room turned by 45° (corners at azimuths 0°, ±90°, 180°),
// fired from −90° upwards so that the 180° corner is crossed mid-scan, under a
// velocity error along (2, 1) and a small rotation error: GVTW's σ jumps at the
// corners, whose perturbed azimuth spans then get the corner uncertainty.
struct CornerRing {
  std::vector<Eigen::Vector3d> points, normals;
  std::vector<double> times;
  std::vector<std::uint8_t> rings;
};

CornerRing corner_ring() {
  CornerRing ring;
  const int n = 720;
  for (int k = 0; k < n; ++k) {
    const double azimuth = std::remainder((-90.0 + 0.5 * k + 0.25) * std::numbers::pi / 180.0, 2 * std::numbers::pi);
    const Eigen::Vector3d direction(std::cos(azimuth), std::sin(azimuth), 0.0);
    // Walls n·p = 5 m with n = (±1, ±1)/√2, the quadrant's.
    const Eigen::Vector3d normal = Eigen::Vector3d(direction.x() >= 0 ? 1 : -1, direction.y() >= 0 ? 1 : -1, 0) /
                                   std::sqrt(2.0);
    const double range = 5.0 / direction.dot(normal);
    ring.points.push_back(range * direction);
    ring.normals.push_back(-normal);
    ring.times.push_back(0.1 * k / n);
    ring.rings.push_back(3);
  }
  return ring;
}

TEST(PointWeights, GvtwCornerTermMarksThePerturbedAzimuthSpanOfEachCorner) {
  const CornerRing ring = corner_ring();
  const Trajectory trajectory = constant_motion(Eigen::Vector3d(10.0, 5.0, 0.0), Eigen::Vector3d(0, 0, 0.3));
  PointWeightParams params;
  params.model = WeightModel::GVTW;
  const PointWeightInput input{ring.points, ring.times, ring.normals, {}, ring.rings, 0.0, false};
  PointWeightWorkspace workspace;
  Outputs plain(ring.points.size()), cornered(ring.points.size());
  compute_point_weights(params, trajectory, input, plain.spans(), workspace);
  params.corner_point_uncertainty_m = 0.5;
  compute_point_weights(params, trajectory, input, cornered.spans(), workspace);

  auto degrees = [](const Eigen::Vector3d& p) { return std::atan2(p.y(), p.x()) * 180.0 / std::numbers::pi; };
  bool near_0 = false, near_90 = false, just_below_180 = false, just_above_minus_180 = false;
  std::size_t marked = 0;
  for (std::size_t i = 0; i < ring.points.size(); ++i) {
    const double added = cornered.sigma_s[i] - plain.sigma_s[i];
    ASSERT_TRUE(std::abs(added) < 1e-12 || std::abs(added - 0.5) < 1e-12) << i << ": " << added;
    if (added < 0.25) continue;
    ++marked;
    const double az = degrees(ring.points[i]);
    const double to_corner = std::min({std::abs(az), std::abs(az - 90.0), 180.0 - std::abs(az)});
    EXPECT_LT(to_corner, 10.0) << "point " << i << " at " << az << "° is far from every corner";
    near_0 = near_0 || std::abs(az) < 10.0;
    near_90 = near_90 || std::abs(az - 90.0) < 10.0;
    just_below_180 = just_below_180 || (az > 170.0);
    just_above_minus_180 = just_above_minus_180 || (az < -170.0);
  }
  EXPECT_TRUE(near_0);
  EXPECT_TRUE(near_90);
  // The 180° corner's span wraps through ±180°.
  EXPECT_TRUE(just_below_180);
  EXPECT_TRUE(just_above_minus_180);
  EXPECT_LT(marked, ring.points.size() / 8);
}

TEST(PointWeights, PerPointPathMatchesThePieces) {
  // compute_point_weights = the piece functions with δ, θ from the trajectory.
  const Trajectory trajectory = constant_motion(Eigen::Vector3d(1.0, -0.5, 0.2), Eigen::Vector3d(0.3, 0.2, 4.0));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points, normals;
  std::vector<double> times;
  for (int i = 0; i < 200; ++i) {
    points.emplace_back(10 * u(rng), 10 * u(rng), u(rng));
    normals.push_back(Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized());
    times.push_back(0.05 + 0.05 * (u(rng) + 1.0));
  }
  PointWeightWorkspace workspace;
  for (const WeightModel model : {WeightModel::VTW, WeightModel::GVTW}) {
    PointWeightParams params;
    params.model = model;
    Outputs out(points.size());
    compute_point_weights(params, trajectory, {points, times, normals, {}, {}, 0.05, true}, out.spans(), workspace);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const SkewPerturbation perturbation = trajectory.skew_integral(0.05, times[i], true);
      const double expected = model == WeightModel::VTW
                                  ? vtw_max_spread(points[i], perturbation)
                                  : 2.0 * gvtw_max_spread(points[i], normals[i], perturbation, 1e-3);
      EXPECT_NEAR(out.sigma_s[i], expected, 1e-12 * (1 + expected));
    }
  }
}

}  // namespace
}  // namespace tumble
