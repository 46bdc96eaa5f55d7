#include "tools/eval/run_plots.hpp"

#include <fmt/format.h>

#include <fstream>

#include "tools/eval/gnuplot.hpp"

namespace tumble::eval {

std::vector<AlignedSample> align_at_first_pose(const PoseSeries& ground_truth, const PoseSeries& estimate) {
  std::vector<AlignedSample> out;
  if (ground_truth.empty()) return out;
  const double t0 = ground_truth.front().t_s, t1 = ground_truth.back().t_s;
  Eigen::Isometry3d estimate_to_truth = Eigen::Isometry3d::Identity();
  for (const TimedPose& pose : estimate) {
    if (pose.t_s < t0 || pose.t_s > t1) continue;
    const Eigen::Isometry3d truth = pose_at(ground_truth, pose.t_s);
    if (out.empty()) estimate_to_truth = truth * to_isometry(pose).inverse();
    AlignedSample s;
    s.t_s = pose.t_s;
    s.truth_m = truth.translation();
    s.estimate_m = estimate_to_truth * pose.position_m;
    s.error_m = (s.estimate_m - s.truth_m).norm();
    out.push_back(s);
  }
  return out;
}

std::string draw_run_plots(const PoseSeries& ground_truth, const PoseSeries& estimate,
                           const std::filesystem::path& dir) {
  const std::vector<AlignedSample> samples = align_at_first_pose(ground_truth, estimate);
  if (samples.empty()) return "no estimated pose inside the ground truth's time span";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  const std::filesystem::path data = dir / "run.dat";
  {
    std::ofstream out(data);
    out << "# t_s truth_x_m truth_y_m truth_z_m estimate_x_m estimate_y_m estimate_z_m error_m\n";
    const double start_s = samples.front().t_s;
    for (const AlignedSample& s : samples)
      out << fmt::format("{:.4f} {:.4f} {:.4f} {:.4f} {:.4f} {:.4f} {:.4f} {:.4f}\n", s.t_s - start_s, s.truth_m.x(),
                         s.truth_m.y(), s.truth_m.z(), s.estimate_m.x(), s.estimate_m.y(), s.estimate_m.z(), s.error_m);
    if (!out) return data.string() + ": cannot write";
  }
  const std::string style =
      "set terminal pngcairo size 800,600 font ',11'\nset grid\nset key below\n"
      "set style line 1 lc rgb '#1f77b4' lw 2\nset style line 2 lc rgb '#d62728' lw 1.5\n";
  struct Plot {
    const char* name;
    std::string body;
  };
  const Plot plots[] = {
      {"trajectory_top",
       fmt::format("set title 'From above: tumbled against ground truth'\nset xlabel 'x (m)'\nset ylabel 'y (m)'\n"
                   "plot '{0}' using 2:3 with lines ls 1 title 'ground truth', "
                   "'{0}' using 5:6 with lines ls 2 title 'tumbled'\n",
                   data.string())},
      {"trajectory_side",
       fmt::format("set title 'From the side: tumbled against ground truth'\nset xlabel 'x (m)'\nset ylabel 'z (m)'\n"
                   "plot '{0}' using 2:4 with lines ls 1 title 'ground truth', "
                   "'{0}' using 5:7 with lines ls 2 title 'tumbled'\n",
                   data.string())},
      {"error",
       fmt::format("set title 'Position error, aligned at the first pose'\nset xlabel 'time (s)'\n"
                   "set ylabel 'error (cm)'\nplot '{0}' using 1:($8*100) with lines ls 2 title 'tumbled'\n",
                   data.string())},
  };
  for (const Plot& plot : plots) {
    const std::string script =
        style + fmt::format("set output '{}'\n", (dir / (std::string(plot.name) + ".png")).string()) + plot.body;
    if (std::string error = run_gnuplot(script, dir / (std::string(plot.name) + ".gp")); !error.empty()) return error;
  }
  return "";
}

}  // namespace tumble::eval
