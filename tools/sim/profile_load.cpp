#include "tools/sim/profile_load.hpp"

#include <cmath>
#include <sstream>

namespace tumble::sim {

namespace {

struct UnitKeys {
  std::string distance, velocity, accel;
};

UnitKeys keys_for(ProfileUnits u) {
  if (u == ProfileUnits::Linear) return {"distance_m", "m_s", "m_s2"};
  return {"angle_rad", "rad_s", "rad_s2"};
}

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void read_step(ScalarProfile& p, const YAML::Node& step, const YamlPath& at, const UnitKeys& k) {
  if (!step.IsMap() || step.size() != 1)
    at.fail("must be one of {hold_s: T}, {ramp: {...}}, {travel: {...}}, {shock: {...}}, {jolt: {...}}");
  const std::string kind = step.begin()->first.as<std::string>();
  const YAML::Node body = step.begin()->second;
  const YamlPath here = at.key(kind);
  const std::string to = "to_" + k.velocity, peak = "peak_" + k.accel, max_v = "max_" + k.velocity;
  const std::string delta = "delta_" + k.velocity, swing = "swing_" + k.velocity;
  if (kind == "hold_s") {
    double d = 0;
    if (!body.IsScalar() || !YAML::convert<double>::decode(body, d) || !(d > 0) || !std::isfinite(d))
      here.fail("must be a positive duration in seconds");
    p.hold(d);
  } else if (kind == "ramp") {
    check_keys(body, here, {to, peak, "rise_s"});
    const double target = read_double(body, here, to);
    const double a = read_positive(body, here, peak);
    const double rise = read_non_negative(body, here, "rise_s", 0.0);
    const double max_rise = std::abs(target - p.end_state().v) / a;
    if (!p.change_velocity(target, a, rise))
      here.key("rise_s").fail("too long for this change: at most " + number(max_rise) + " s (|change| / " + peak + ")");
  } else if (kind == "travel") {
    check_keys(body, here, {k.distance, max_v, peak});
    if (p.end_state().v != 0.0) here.fail("must start at rest (add a ramp to 0 before it)");
    p.travel(read_double(body, here, k.distance), read_positive(body, here, max_v), read_positive(body, here, peak));
  } else if (kind == "shock") {
    check_keys(body, here, {peak, delta, "restitution"});
    const double a = read_positive(body, here, peak);
    const bool has_delta = has_key(body, delta), has_restitution = has_key(body, "restitution");
    if (has_delta == has_restitution) here.fail("give exactly one of " + delta + " or restitution");
    double dv = 0;
    if (has_delta) {
      dv = read_double(body, here, delta);
      if (dv == 0.0) here.key(delta).fail("must be nonzero");
    } else {
      const double e = read_double(body, here, "restitution");
      if (e < 0 || e > 1) here.key("restitution").fail("must be in [0, 1]");
      const double v = p.end_state().v;
      if (v == 0.0) here.fail("an end-stop shock (restitution) needs a nonzero velocity before it");
      dv = -(1.0 + e) * v;  // stop, then rebound at e times the impact speed
    }
    p.shock(a, dv);
  } else if (kind == "jolt") {
    check_keys(body, here, {peak, swing});
    const double a = read_double(body, here, peak);
    if (a == 0.0) here.key(peak).fail("must be nonzero (its sign is the first half's)");
    p.jolt(a, 4.0 * read_positive(body, here, swing) / std::abs(a));
  } else {
    at.fail("unknown step '" + kind + "' (allowed: hold_s, ramp, travel, shock, jolt)");
  }
}

}  // namespace

ScalarProfile read_profile(const YAML::Node& steps, const YamlPath& at, ProfileUnits units) {
  if (!steps || !steps.IsSequence() || steps.size() == 0) at.fail("must be a non-empty list of steps");
  const UnitKeys k = keys_for(units);
  ScalarProfile p;
  for (std::size_t i = 0; i < steps.size(); ++i) read_step(p, steps[i], at.index(i), k);
  return p;
}

}  // namespace tumble::sim
