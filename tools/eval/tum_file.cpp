#include "tools/eval/tum_file.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "tools/eval/text_fields.hpp"

namespace tumble::eval {
namespace {

// Anything further from 1 is not a rotation written with 9 decimals.
constexpr double kUnitQuaternionTolerance = 1e-4;

}  // namespace

PoseSeries read_tum(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  PoseSeries series;
  std::string line;
  for (int line_number = 1; std::getline(in, line); ++line_number) {
    const auto where = [&] { return path.string() + ":" + std::to_string(line_number) + ": "; };
    const std::vector<std::string_view> fields = split_whitespace(line);
    if (fields.empty() || fields.front().front() == '#') continue;
    if (fields.size() != 8)
      throw std::runtime_error(where() + "expected 8 numbers (t x y z qx qy qz qw), got " +
                               std::to_string(fields.size()) + " fields");
    std::array<double, 8> v{};
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::optional<double> value = parse_double(fields[i]);
      if (!value || !std::isfinite(*value))
        throw std::runtime_error(where() + "field " + std::to_string(i + 1) + " '" + std::string(fields[i]) +
                                 "' is not a finite number");
      v[i] = *value;
    }
    TimedPose pose;
    pose.t_s = v[0];
    pose.position_m = {v[1], v[2], v[3]};
    pose.orientation = Eigen::Quaterniond(v[7], v[4], v[5], v[6]);
    if (std::abs(pose.orientation.norm() - 1.0) > kUnitQuaternionTolerance)
      throw std::runtime_error(where() + "quaternion is not unit (norm " + std::to_string(pose.orientation.norm()) +
                               ")");
    pose.orientation.normalize();
    if (!series.empty() && pose.t_s <= series.back().t_s)
      throw std::runtime_error(where() + "time " + std::string(fields[0]) + " does not increase");
    series.push_back(pose);
  }
  if (in.bad()) throw std::runtime_error(path.string() + ": read error");
  return series;
}

void write_tum(const std::filesystem::path& path, const PoseSeries& series) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
  out << "# t x y z qx qy qz qw\n";
  char line[256];
  for (const TimedPose& p : series) {
    const Eigen::Quaterniond& q = p.orientation;
    std::snprintf(line, sizeof line, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", p.t_s, p.position_m.x(),
                  p.position_m.y(), p.position_m.z(), q.x(), q.y(), q.z(), q.w());
    out << line;
  }
  if (!out) throw std::runtime_error(path.string() + ": write error");
}

}  // namespace tumble::eval
