// Ring records -> tumble LCM messages. The target messages are reused, so
// their strings and vectors stop allocating once grown.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "daemon/records.hpp"
#include "tumble/odometry_t.hpp"
#include "tumble/registration_t.hpp"

namespace tumble::daemon {

// LCM's utime: microseconds of the host clock.
std::int64_t to_utime(double t_s);

void to_lcm(const TrajectoryRecord& sample, std::int64_t seq, float latency_ms, tumble::odometry_t& out);

// stage_names: RegistrationStage::stage_names(); latency_ms: scan complete -> publish.
void to_lcm(const RegistrationRecord& registration, const std::vector<std::string>& stage_names, float latency_ms,
            tumble::registration_t& out);

}  // namespace tumble::daemon
