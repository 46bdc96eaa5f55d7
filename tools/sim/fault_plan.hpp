// What `tumble-sim faults` injects into a recorded run: the network's and the
// serial line's misbehaviour, each fault alone or combined, drawn from a seed.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace tumble::sim {

// [start_s, start_s + duration_s), seconds from the run's first record.
struct FaultWindow {
  double start_s = 0.0;
  double duration_s = 0.0;
};

struct ClockJump {
  double at_s = 0.0;    // seconds from the run's first record
  double jump_s = 0.0;  // added to the header time of every lidar packet from then on
};

// From at_s on, the lidar's stream from lead_s earlier, kSecondLidarSpeedup
// times as fast, restamped to its arrival time.
struct SecondLidar {
  double at_s = 0.0;
  double lead_s = 0.0;
};
inline constexpr double kSecondLidarSpeedup = 1.5;

struct FaultPlan {
  std::uint64_t seed = 1;
  double drop_lidar = 0.0;     // chance an MSOP packet is lost
  double dup_lidar = 0.0;      // chance an MSOP packet arrives twice
  double swap_lidar = 0.0;     // chance an MSOP packet swaps places with the next one
  double foreign_lidar = 0.0;  // chance an MSOP packet is followed by one from a foreign sender
  double imu_garbage = 0.0;    // chance a serial read is preceded by 1..40 garbage bytes
  double imu_nan = 0.0;        // chance a serial read's MTData2 frames carry a NaN rate of turn
  // Mean extra delay of a lidar datagram's arrival (exponential, with stalls
  // that hold back what follows); header times and order are kept, as a
  // switch's queue or a busy host does.
  double lidar_delay_s = 0.0;
  std::optional<FaultWindow> lidar_gap;  // no lidar datagram arrives
  std::optional<FaultWindow> imu_gap;    // no serial read arrives
  std::optional<ClockJump> lidar_clock_jump;
  std::optional<FaultWindow> motor_stall;  // the lidar's head stands still, its lasers firing on
  // From this time on the lidar's DIFOPs carry another calibration.
  std::optional<double> difop_change_at_s;
  // A second host sends the lidar's own stream (a replay someone forgot to stop).
  std::optional<SecondLidar> second_lidar;
};

// Throws std::invalid_argument naming the option and what it allows.
void validate(const FaultPlan& plan);

// "T,D" for --lidar-gap / --imu-gap / --motor-stall, "T,S" for
// --lidar-clock-jump and "T,L" for --second-lidar; throws
// std::invalid_argument naming the option when text is not two numbers.
FaultWindow parse_fault_window(const std::string& option, const std::string& text);
ClockJump parse_clock_jump(const std::string& option, const std::string& text);
SecondLidar parse_second_lidar(const std::string& option, const std::string& text);

}  // namespace tumble::sim
