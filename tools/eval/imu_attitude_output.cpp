// The outputs of `tumble-eval imu`: report, TUM attitude, roll/pitch plot.
#include <cstdio>
#include <fstream>
#include <numbers>

#include "core/angles.hpp"
#include "tools/eval/gnuplot.hpp"
#include "tools/eval/imu_attitude.hpp"

namespace tumble::eval {
namespace {

constexpr std::size_t kMaxPlotPoints = 5000;

std::string format(const char* pattern, auto... values) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, values...);
  return text;
}

std::string stats_row(const std::string& what, const std::optional<AngleStats>& s, const std::string& absent) {
  if (!s) return "| " + what + " | " + absent + " | | | |\n";
  return format("| %s | %zu | %.3f | %.3f | %.3f |\n", what.c_str(), s->count, s->median_deg, s->p95_deg,
                s->max_deg);
}

}  // namespace

std::string imu_report_markdown(const ImuEvaluation& e) {
  std::string md = "# tumble-eval imu: " + e.recording + "\n\n";
  md += format("%s, %zu IMU samples over %.2f s.", e.format.c_str(), e.samples, e.duration_s);
  md += e.reader_problem.empty() ? " The reader found nothing wrong.\n\n" : " Reader: " + e.reader_problem + "\n\n";
  md += "The fuser runs alone (no lidar corrections, T_LI = identity): its attitude is the gyro integrated, "
        "corrected towards the accelerometer's gravity by Madgwick. Tilt = the angle between two 'up' "
        "directions in the IMU frame (roll and pitch; yaw is not observable from gravity).\n\n";
  if (e.initialized_at_s)
    md += format("Fuser initialised at t = %.3f s; gyro bias from its still window: [%.5f, %.5f, %.5f] rad/s "
                 "([%.3f, %.3f, %.3f] deg/s).\n\n",
                 *e.initialized_at_s, e.fuser_gyro_bias_rad_s.x(), e.fuser_gyro_bias_rad_s.y(),
                 e.fuser_gyro_bias_rad_s.z(), e.fuser_gyro_bias_rad_s.x() * kRadToDeg,
                 e.fuser_gyro_bias_rad_s.y() * kRadToDeg, e.fuser_gyro_bias_rad_s.z() * kRadToDeg);
  else
    md += "The fuser never initialised: the recording has no still window as long as --fuser-static-s.\n\n";

  md += "## Still periods\n\n";
  if (e.still_periods.empty()) md += "None found.\n\n";
  else {
    md += "| from (s) | to (s) | samples | mean gyro = bias there (deg/s) | tilt of ours on entry (deg) |\n"
          "|---|---|---|---|---|\n";
    for (const StillPeriod& p : e.still_periods)
      md += format("| %.3f | %.3f | %zu | [%.3f, %.3f, %.3f] | %s |\n", p.begin_s, p.end_s, p.samples,
                   p.mean_gyro_rad_s.x() * kRadToDeg, p.mean_gyro_rad_s.y() * kRadToDeg,
                   p.mean_gyro_rad_s.z() * kRadToDeg,
                   p.entry_tilt_deg ? format("%.3f", *p.entry_tilt_deg).c_str() : "before initialisation");
    md += "\n";
  }

  md += "## Tilt (deg)\n\n| compared | samples | median | p95 | max |\n|---|---|---|---|---|\n";
  md += stats_row("ours vs still accelerometer", e.ours_vs_accel, "no still sample after initialisation");
  md += stats_row("device's own orientation vs still accelerometer", e.device_vs_accel, "the recording has no device orientation");
  md += stats_row("ours vs device's own orientation (all samples)", e.ours_vs_device, "the recording has no device orientation");
  md += "\n";

  md += "## Clipping (StatusWord)\n\n";
  md += format("%llu samples clipped on some axis; gyro x/y/z %llu/%llu/%llu, accelerometer x/y/z %llu/%llu/%llu.\n",
               static_cast<unsigned long long>(e.samples_clipped), static_cast<unsigned long long>(e.gyro_clipped[0]),
               static_cast<unsigned long long>(e.gyro_clipped[1]), static_cast<unsigned long long>(e.gyro_clipped[2]),
               static_cast<unsigned long long>(e.accel_clipped[0]), static_cast<unsigned long long>(e.accel_clipped[1]),
               static_cast<unsigned long long>(e.accel_clipped[2]));
  return md;
}

void write_attitude_tum(const ImuEvaluation& e, const std::filesystem::path& path) {
  std::ofstream out(path);
  out << "# t x y z qx qy qz qw: the IMU's attitude from tumble-eval imu (the fuser alone; position not estimated)\n";
  for (const AttitudeSample& a : e.attitude)
    out << format("%.6f 0 0 0 %.9f %.9f %.9f %.9f\n", a.t_s, a.q_wi.x(), a.q_wi.y(), a.q_wi.z(), a.q_wi.w());
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

std::string draw_roll_pitch(const ImuEvaluation& e, const std::filesystem::path& script_path,
                            const std::filesystem::path& png_path) {
  const bool device = !e.attitude.empty() && e.attitude.front().up_device.has_value();
  const std::size_t stride = std::max<std::size_t>(1, e.attitude.size() / kMaxPlotPoints);
  std::string data = "$attitude << EOD\n";
  for (std::size_t i = 0; i < e.attitude.size(); i += stride) {
    const AttitudeSample& a = e.attitude[i];
    const Eigen::Vector2d ours = roll_pitch_rad(a.up_ours) * kRadToDeg;
    const Eigen::Vector2d accel = roll_pitch_rad(a.accel_m_s2) * kRadToDeg;
    const Eigen::Vector2d dev = a.up_device ? Eigen::Vector2d(roll_pitch_rad(*a.up_device) * kRadToDeg) : ours;
    data += format("%.4f %.4f %.4f %.4f %.4f %s %s\n", a.t_s - e.attitude.front().t_s, ours.x(), ours.y(), dev.x(),
                   dev.y(), a.still ? format("%.4f", accel.x()).c_str() : "NaN",
                   a.still ? format("%.4f", accel.y()).c_str() : "NaN");
  }
  data += "EOD\n";
  std::string script = "# tumble-eval imu roll/pitch plot; redraw with: gnuplot THIS_FILE\n";
  script += "set terminal pngcairo size 1200,800 font 'sans,11'\nset output '" + png_path.string() + "'\n";
  script += data;
  script += "set multiplot layout 2,1 title 'IMU attitude: the fuser alone" +
            std::string(device ? " beside the device filter" : "") + "'\n";
  script += "set grid\nset key outside right\nset xlabel 'time since initialisation (s)'\n";
  for (const bool pitch : {false, true}) {
    const int col = pitch ? 3 : 2;
    script += std::string("set ylabel '") + (pitch ? "pitch" : "roll") + " (deg)'\n";
    script += "plot $attitude using 1:" + std::to_string(col) + " with lines lw 2 lc rgb '0x1f77b4' title 'ours'";
    if (device)
      script += ", \\\n     $attitude using 1:" + std::to_string(col + 2) +
                " with lines lw 1 lc rgb '0xff7f0e' title 'device'";
    script += ", \\\n     $attitude using 1:" + std::to_string(col + 4) +
              " with points pt 7 ps 0.3 lc rgb 'black' title 'still accelerometer'\n";
  }
  script += "unset multiplot\n";
  return run_gnuplot(script, script_path);
}

}  // namespace tumble::eval
