// One run of a scenario made concrete: the scene and motion loaded, and every
// choice the seed makes (lidar unit, phases, IMU clock) drawn once, so the
// sensor streams can be replayed any number of times with the same bytes.
#pragma once

#include <memory>

#include "tools/sim/scenario.hpp"
#include "tools/sim/scene.hpp"

namespace tumble::sim {

// How long a run of this scenario lasts (its duration_s, else the motion's).
double scenario_duration_s(const Scenario& scenario);

class SimRun {
 public:
  // Throws SimConfigError for a bad scene or motion, or a duration beyond the motion's.
  explicit SimRun(Scenario scenario);

  const Scenario& scenario() const { return scenario_; }
  const Scene& scene() const { return scene_; }
  const Motion& motion() const { return *motion_; }
  double duration_s() const { return duration_s_; }
  const LidarUnit& lidar_unit() const { return lidar_unit_; }
  const LidarTiming& lidar_timing() const { return lidar_timing_; }
  const ImuClock& imu_clock() const { return imu_clock_; }
  const People& people() const { return people_; }

  // Moves run time 0 to another moment of the host clock (live mode starts now).
  void set_epoch_ns(std::int64_t epoch_ns) {
    scenario_.epoch_ns = epoch_ns;
    lidar_timing_.epoch_ns = epoch_ns;
  }

  // Fresh streams over the whole run; they keep references to this run.
  LidarStream lidar_stream() const;
  ImuStream imu_stream() const;

 private:
  Scenario scenario_;
  Scene scene_;
  std::unique_ptr<Motion> motion_;
  double duration_s_ = 0.0;
  LidarUnit lidar_unit_;
  LidarTiming lidar_timing_;
  ImuClock imu_clock_;
  People people_;
};

}  // namespace tumble::sim
