#include "tools/sim/sim_run.hpp"

#include <cmath>
#include <sstream>

#include "tools/sim/motion_load.hpp"
#include "tools/sim/scene_load.hpp"

namespace tumble::sim {
namespace {

std::unique_ptr<Motion> load_scenario_motion(const Scenario& s) {
  MotionLoadOptions options;
  options.source_name = s.motion_ref == "inline" ? s.source_name : s.motion_ref;
  options.key_path = s.motion_ref == "inline" ? "motion" : "";
  options.seed = s.motion_seed;
  return load_motion(s.motion, options);
}

}  // namespace

double scenario_duration_s(const Scenario& scenario) {
  return scenario.duration_s.value_or(load_scenario_motion(scenario)->duration_s());
}

SimRun::SimRun(Scenario scenario)
    : scenario_(std::move(scenario)),
      scene_(load_scene(scenario_.scene_path.string())),
      motion_(load_scenario_motion(scenario_)) {
  const double motion_s = motion_->duration_s();
  duration_s_ = scenario_.duration_s.value_or(motion_s);
  if (duration_s_ > motion_s + 1e-9) {
    std::ostringstream why;
    why << scenario_.source_name << ": duration_s: " << duration_s_ << " s is longer than the motion (" << motion_s
        << " s)";
    throw SimConfigError(why.str());
  }

  const Scenario& s = scenario_;
  lidar_unit_ = make_lidar_unit(s.lidar_unit_seed.value_or(s.seed), s.lidar);

  // Phases and clocks: whatever the capture happened to catch.
  SensorRng rng(s.seed, "run-timing");
  lidar_timing_.epoch_ns = s.epoch_ns;
  lidar_timing_.first_packet_ns = static_cast<std::int64_t>(rng.uniform(0.0, 1332.0)) * 1000;
  lidar_timing_.azimuth_at_zero_deg = rng.uniform(0.0, 360.0);
  const double difop_phase_s = rng.uniform(0.0, s.lidar_link.difop_period_s);
  lidar_timing_.first_difop_ns = std::llround(s.difop_phase_s.value_or(difop_phase_s) * 1e9);

  const double drift_ppm = rng.uniform(-10.0, 10.0);
  const double first_sample_s = rng.uniform(0.0, 1.0 / s.imu.rate_hz);
  const double start_s = rng.uniform(60.0, 3600.0);
  const auto counter = static_cast<std::uint16_t>(rng.next_u64() & 0xFFFF);
  imu_clock_.drift_ppm = s.imu_clock_drift_ppm.value_or(drift_ppm);
  imu_clock_.first_sample_s = first_sample_s;
  const double ticks_per_sample = 10'000.0 / s.imu.rate_hz;
  // Samples sit on the device's own grid of whole sample periods.
  imu_clock_.first_sample_time_fine =
      static_cast<std::uint32_t>(std::floor(s.imu_sample_time_start_s.value_or(start_s) * 10'000.0 / ticks_per_sample) *
                                 ticks_per_sample);
  imu_clock_.first_packet_counter = counter;
  imu_clock_.imu_time_offset_s = s.imu_time_offset_s;
  // Last, from their own streams: people move no sensor's random numbers.
  if (s.people.any()) people_ = People(s.people, *motion_, duration_s_, s.seed);
}

LidarStream SimRun::lidar_stream() const {
  return LidarStream(scenario_.lidar, lidar_unit_, scenario_.lidar_link, lidar_timing_, scene_, *motion_,
                     scenario_.seed, duration_s_, &people_);
}

ImuStream SimRun::imu_stream() const {
  return ImuStream(scenario_.imu, imu_clock_, scenario_.imu_link, scenario_.T_LI, *motion_, scenario_.seed,
                   scenario_.imu_noise, duration_s_);
}

}  // namespace tumble::sim
