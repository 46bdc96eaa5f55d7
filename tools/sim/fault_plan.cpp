#include "tools/sim/fault_plan.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <utility>

namespace tumble::sim {
namespace {

void check_chance(const char* option, double p) {
  if (!(p >= 0.0 && p <= 1.0))
    throw std::invalid_argument(std::string(option) + " " + std::to_string(p) + ": must be a probability in [0, 1]");
}

void check_window(const char* option, const std::optional<FaultWindow>& w) {
  if (w && !(std::isfinite(w->start_s) && w->start_s >= 0.0 && std::isfinite(w->duration_s) && w->duration_s > 0.0))
    throw std::invalid_argument(std::string(option) + ": needs T >= 0 and D > 0 (seconds)");
}

// Two comma-separated finite numbers, nothing else.
std::pair<double, double> parse_pair(const std::string& option, const std::string& text, const char* form) {
  const auto fail = [&] {
    return std::invalid_argument(option + " '" + text + "': expected " + form + " (two numbers, seconds)");
  };
  const auto comma = text.find(',');
  if (comma == std::string::npos) throw fail();
  const auto number = [&](const std::string& part) {
    if (part.empty()) throw fail();
    char* end = nullptr;
    const double v = std::strtod(part.c_str(), &end);
    if (end != part.c_str() + part.size() || !std::isfinite(v)) throw fail();
    return v;
  };
  return {number(text.substr(0, comma)), number(text.substr(comma + 1))};
}

}  // namespace

void validate(const FaultPlan& plan) {
  check_chance("--drop-lidar", plan.drop_lidar);
  check_chance("--dup-lidar", plan.dup_lidar);
  check_chance("--swap-lidar", plan.swap_lidar);
  check_chance("--foreign-lidar", plan.foreign_lidar);
  check_chance("--imu-garbage", plan.imu_garbage);
  check_chance("--imu-nan", plan.imu_nan);
  check_window("--motor-stall", plan.motor_stall);
  if (plan.difop_change_at_s && !(*plan.difop_change_at_s >= 0.0))
    throw std::invalid_argument("--difop-change: needs T >= 0 (seconds)");
  if (plan.second_lidar && !(plan.second_lidar->at_s >= 0.0 && plan.second_lidar->lead_s > 0.0))
    throw std::invalid_argument("--second-lidar: needs T >= 0 and a lead L > 0 (seconds)");
  if (!(plan.lidar_delay_s >= 0.0 && plan.lidar_delay_s <= 1.0))
    throw std::invalid_argument("--lidar-delay " + std::to_string(plan.lidar_delay_s) +
                                ": must be a mean delay in [0, 1] s");
  check_window("--lidar-gap", plan.lidar_gap);
  check_window("--imu-gap", plan.imu_gap);
  if (plan.lidar_clock_jump && !(plan.lidar_clock_jump->at_s >= 0.0 && plan.lidar_clock_jump->jump_s != 0.0))
    throw std::invalid_argument("--lidar-clock-jump: needs T >= 0 and a jump S != 0 (seconds)");
}

FaultWindow parse_fault_window(const std::string& option, const std::string& text) {
  const auto [t, d] = parse_pair(option, text, "T,D");
  return {t, d};
}

ClockJump parse_clock_jump(const std::string& option, const std::string& text) {
  const auto [t, s] = parse_pair(option, text, "T,S");
  return {t, s};
}

SecondLidar parse_second_lidar(const std::string& option, const std::string& text) {
  const auto [t, l] = parse_pair(option, text, "T,L");
  return {t, l};
}

}  // namespace tumble::sim
