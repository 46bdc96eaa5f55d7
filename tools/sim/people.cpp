#include "tools/sim/people.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "tools/sim/ray_cast.hpp"
#include "tools/sim/sensor_rng.hpp"

namespace tumble::sim {
namespace {

// The puller's track is sampled at 100 Hz: at 3.5 m/s a linear
// interpolation between samples is off by well under a millimetre.
constexpr double kPullerStepS = 0.01;
// Below this the robot has no direction of travel to follow: the puller keeps theirs.
constexpr double kMinTravelSpeedMS = 0.2;

double wrap_pi(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

Eigen::Vector2d robot_xy_at(const Motion& robot, double t_s) { return robot.at(t_s).T_wb.translation().head<2>(); }

Eigen::Vector2d walker_xy(const WalkerPath& w, double t_s) {
  const double length = (w.to_m - w.from_m).norm();
  if (length < 1e-9) return w.from_m;
  const double loop = 2.0 * length;
  double s = std::fmod(w.start_m + w.speed_m_s * std::max(t_s, 0.0), loop);
  if (s > length) s = loop - s;
  return w.from_m + (s / length) * (w.to_m - w.from_m);
}

// Where the robot is every kClearanceStepS, to keep drawn walkers off it.
constexpr double kClearanceStepS = 0.05;
constexpr double kWalkerClearanceM = 1.0;
constexpr int kWalkerStartDraws = 20;

double closest_approach_m(const WalkerPath& w, const std::vector<Eigen::Vector2d>& robot_track) {
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < robot_track.size(); ++k)
    closest = std::min(closest, (walker_xy(w, static_cast<double>(k) * kClearanceStepS) - robot_track[k]).norm());
  return closest;
}

// A path through the robot's position at a random moment of the run, in a
// random direction: people cross where the robot goes (through the scene's
// objects too: the paths do not know the scene). Of up to 20 starting
// points the first that never comes within 1 m of the robot is taken (else
// the one that comes least close): people cross its path, not its cage.
WalkerPath draw_walker(SensorRng& rng, const PeopleConfig& c, const std::vector<Eigen::Vector2d>& robot_track) {
  const auto at = static_cast<std::size_t>(rng.uniform(0.0, static_cast<double>(robot_track.size())));
  const Eigen::Vector2d crossing = robot_track[std::min(at, robot_track.size() - 1)];
  const double heading = rng.uniform(0.0, 2.0 * std::numbers::pi);
  const double length = rng.uniform(c.walker_min_path_m, c.walker_max_path_m);
  const double crossing_at = rng.uniform(0.2, 0.8);  // of the path's length
  const Eigen::Vector2d along(std::cos(heading), std::sin(heading));
  WalkerPath w;
  w.from_m = crossing - crossing_at * length * along;
  w.to_m = crossing + (1.0 - crossing_at) * length * along;
  w.speed_m_s = rng.uniform(c.walker_min_speed_m_s, c.walker_max_speed_m_s);
  double best_start_m = 0.0, best_approach_m = -1.0;
  for (int draw = 0; draw < kWalkerStartDraws && best_approach_m < kWalkerClearanceM; ++draw) {
    w.start_m = rng.uniform(0.0, 2.0 * length);
    const double approach_m = closest_approach_m(w, robot_track);
    if (approach_m > best_approach_m) {
      best_approach_m = approach_m;
      best_start_m = w.start_m;
    }
  }
  w.start_m = best_start_m;
  return w;
}

}  // namespace

People::People(const PeopleConfig& config, const Motion& robot, double duration_s, std::uint64_t scenario_seed)
    : config_(config) {
  const std::uint64_t seed = config.seed.value_or(scenario_seed);
  if (config.walkers) {
    walkers_ = config.walker_paths;
    SensorRng rng(seed, "people-walkers");
    if (walkers_.empty()) {
      std::vector<Eigen::Vector2d> robot_track(static_cast<std::size_t>(duration_s / kClearanceStepS) + 1);
      for (std::size_t k = 0; k < robot_track.size(); ++k)
        robot_track[k] = robot_xy_at(robot, static_cast<double>(k) * kClearanceStepS);
      for (int k = 0; k < config.walker_count; ++k) walkers_.push_back(draw_walker(rng, config, robot_track));
    }
  }
  if (config.rope_puller) {
    SensorRng rng(seed, "people-rope-puller");
    puller_surge_phase_rad_ = rng.uniform(0.0, 2.0 * std::numbers::pi);
    const auto samples = static_cast<std::size_t>(std::ceil(duration_s / kPullerStepS)) + 1;
    std::vector<Eigen::Vector2d> velocity(samples);
    robot_xy_.resize(samples);
    for (std::size_t k = 0; k < samples; ++k) {
      const MotionState state = robot.at(static_cast<double>(k) * kPullerStepS);
      robot_xy_[k] = state.T_wb.translation().head<2>();
      velocity[k] = state.v_w.head<2>();
    }
    // Before the robot moves the puller already stands where it will go.
    double heading = 0.0;
    const auto first_move = std::find_if(velocity.begin(), velocity.end(),
                                         [](const Eigen::Vector2d& v) { return v.norm() > kMinTravelSpeedMS; });
    if (first_move != velocity.end()) heading = std::atan2(first_move->y(), first_move->x());
    // The puller turns with the robot's direction of travel, smoothly and a
    // little late (the cage's own wobble and jolts do not turn them); the
    // unwrapped angle walks them round the cage when it reverses.
    const double follow = 1.0 - std::exp(-kPullerStepS / config.puller_heading_lag_s);
    puller_heading_rad_.resize(samples);
    for (std::size_t k = 0; k < samples; ++k) {
      if (velocity[k].norm() > kMinTravelSpeedMS)
        heading += follow * wrap_pi(std::atan2(velocity[k].y(), velocity[k].x()) - heading);
      puller_heading_rad_[k] = heading;
    }
  }
}

Eigen::Vector2d People::puller_xy(double t_s) const {
  const double u = std::clamp(t_s / kPullerStepS, 0.0, static_cast<double>(robot_xy_.size() - 1));
  // At least two samples (duration > 0): the last interval takes t = duration.
  const std::size_t k = std::min(static_cast<std::size_t>(u), robot_xy_.size() - 2), k1 = k + 1;
  const double f = u - static_cast<double>(k);
  const Eigen::Vector2d robot = (1.0 - f) * robot_xy_[k] + f * robot_xy_[k1];
  const double heading = (1.0 - f) * puller_heading_rad_[k] + f * puller_heading_rad_[k1];
  const double ahead = config_.puller_ahead_m +
                       config_.puller_surge_m * std::sin(2.0 * std::numbers::pi * t_s / config_.puller_surge_period_s +
                                                         puller_surge_phase_rad_);
  return robot + ahead * Eigen::Vector2d(std::cos(heading), std::sin(heading));
}

Eigen::Vector2d People::position_xy(std::size_t i, double t_s) const {
  return i < walkers_.size() ? walker_xy(walkers_[i], t_s) : puller_xy(t_s);
}

std::optional<Hit> People::cast(double t_s, const Eigen::Vector3d& origin_w, const Eigen::Vector3d& dir_unit_w,
                                double max_range_m) const {
  Primitive person;
  person.shape = Shape::Cylinder;
  person.radius_m = config_.radius_m;
  person.half_size.z() = 0.5 * config_.height_m;
  std::optional<Hit> nearest;
  double reach_m = max_range_m;
  for (std::size_t i = 0; i < count(); ++i) {
    const Eigen::Vector2d xy = position_xy(i, t_s);
    person.pose_w.translation() = Eigen::Vector3d(xy.x(), xy.y(), config_.floor_z_m + 0.5 * config_.height_m);
    const auto hit = intersect(person, Ray{origin_w, dir_unit_w}, reach_m);
    if (!hit) continue;
    reach_m = hit->t_m;
    nearest = Hit{hit->t_m, config_.reflectivity, hit->normal_w, Material::Diffuse};
  }
  return nearest;
}

}  // namespace tumble::sim
