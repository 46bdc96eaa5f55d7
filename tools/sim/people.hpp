// Moving people in the scene: walkers crossing it and the
// person who pulls the rolling cage's rope, walking ahead of it. Each person
// is a vertical capped cylinder standing on the floor; the lidar model tests
// them beside the static scene's BVH, for every beam at its own firing time.
// Their randomness comes from their own streams, so a run with people and the
// same run without them differ only in the beams that meet a person.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "tools/sim/motion.hpp"
#include "tools/sim/scene.hpp"

namespace tumble::sim {

// Back and forth between two floor points at a constant speed, turning on the
// spot at each end; start_m is how far along the out-and-back loop it is at t = 0.
struct WalkerPath {
  Eigen::Vector2d from_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d to_m = Eigen::Vector2d::Zero();
  double speed_m_s = 1.2;
  double start_m = 0.0;
};

struct PeopleConfig {
  std::optional<std::uint64_t> seed;  // default: the scenario's seed
  // A standing adult: shoulder half-width, height, and clothing of mixed
  // colours (diffuse reflectance of textiles in the near infrared is 0.2-0.6).
  double radius_m = 0.25;
  double height_m = 1.75;
  double reflectivity = 0.4;
  double floor_z_m = 0.0;

  bool walkers = false;
  int walker_count = 3;                  // drawn paths, when walker_paths is empty
  double walker_min_speed_m_s = 1.0;     // drawn speeds: uniform in [min, max]
  double walker_max_speed_m_s = 1.5;
  double walker_min_path_m = 8.0;        // drawn path lengths: uniform in [min, max]
  double walker_max_path_m = 16.0;
  std::vector<WalkerPath> walker_paths;  // listed in the scenario instead of drawn

  bool rope_puller = false;
  double puller_ahead_m = 2.0;        // mean distance ahead of the robot
  double puller_surge_m = 0.3;        // the rope slackens and tightens: +- this, smoothly
  double puller_surge_period_s = 4.0;
  double puller_heading_lag_s = 0.5;  // time constant of turning with the robot's direction of travel

  bool any() const { return walkers || rope_puller; }
};

class People {
 public:
  People() = default;  // nobody
  // Draws the walkers' paths (those not listed) around the robot's route and
  // precomputes the puller's track from the robot's ground truth.
  People(const PeopleConfig& config, const Motion& robot, double duration_s, std::uint64_t scenario_seed);

  bool empty() const { return walkers_.empty() && puller_heading_rad_.empty(); }
  std::size_t count() const { return walkers_.size() + (puller_heading_rad_.empty() ? 0 : 1); }
  const std::vector<WalkerPath>& walkers() const { return walkers_; }

  // Where person i (walkers first, then the puller) stands at run time t: the
  // centre of their footprint on the floor.
  Eigen::Vector2d position_xy(std::size_t i, double t_s) const;

  // Nearest person within (0, max_range_m) along the ray at run time t.
  std::optional<Hit> cast(double t_s, const Eigen::Vector3d& origin_w, const Eigen::Vector3d& dir_unit_w,
                          double max_range_m) const;

 private:
  Eigen::Vector2d puller_xy(double t_s) const;

  PeopleConfig config_;
  std::vector<WalkerPath> walkers_;
  // The puller's track, sampled every kPullerStepS from t = 0.
  std::vector<Eigen::Vector2d> robot_xy_;
  std::vector<double> puller_heading_rad_;
  double puller_surge_phase_rad_ = 0.0;
};

}  // namespace tumble::sim
