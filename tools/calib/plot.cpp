#include "tools/calib/plot.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace tumble::calib {
namespace {

// A gnuplot single-quoted string: a quote is written twice.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\'') out += '\'';
    out += c;
  }
  return out + "'";
}

}  // namespace

std::string plot_script(const AxisCalibration& axis, const std::filesystem::path& png) {
  const bool linear = axis.rig == Rig::Rail;
  const char* unit = linear ? "m/s" : "rad/s";
  double max_speed = 0;
  for (const BinSummary& b : axis.bins) max_speed = std::max(max_speed, b.speed_median);

  std::ostringstream s;
  s.precision(9);
  s << "# tumble-calib: " << (linear ? "linear" : "angular") << " speed uncertainty (paper Fig. 5)\n";
  s << "$bins << EOD\n# speed residual_q1 residual_median residual_q3 sigma_q3 deskew_sigma_median deskew_sigma_q3\n";
  for (const BinSummary& b : axis.bins)
    s << b.speed_median << ' ' << b.residual_m.q1 << ' ' << b.residual_m.median << ' ' << b.residual_m.q3 << ' '
      << b.sigma.q3 << ' ' << b.deskew_sigma.median << ' ' << b.deskew_sigma.q3 << '\n';
  s << "EOD\n";
  s << "offset = " << axis.noise.mean_m << '\n';
  if (linear) {
    s << "B = " << axis.lognormal.beta << "\nK = " << axis.lognormal.kappa_m_s << "\nL = " << axis.lognormal.lambda
      << "\nsigma(v) = v <= 0 ? 0 : L / (B * v * sqrt(2 * pi)) * exp(-log(v / K)**2 / (2 * B**2))\n";
  } else {
    s << "P = " << axis.cubic.phi_rad_s << "\nsigma(w) = (w / P)**3\n";
  }
  s << "set terminal pngcairo size 900,1000 font ',11'\n"
    << "set output " << quoted(png.string()) << '\n'
    << "set multiplot layout 2,1\nset grid\nset key top left\nset samples 400\n"
    << "set xrange [0:" << std::max(max_speed * 1.05, 1e-3) << "]\n"
    << "set xlabel " << quoted(std::string(linear ? "linear speed v (" : "angular speed ω (") + unit + ")") << '\n'
    << "set ylabel " << quoted(linear ? "mean |e·n|, surfaces ⟂ motion (m)" : "mean Euclidean residual (m)") << '\n'
    << "set title "
    << quoted(std::string(linear ? "Rail" : "Turntable") + ": registration residual of de-skewed scans vs speed")
    << '\n'
    << "plot $bins using 1:2:4 with filledcurves fillcolor rgb '#a6c8ff' title 'first-third quartile', \\\n"
    << "     $bins using 1:3 with linespoints lw 2 lc rgb '#1f4fbf' pt 7 title 'median', \\\n"
    << "     offset with lines dt 3 lw 2 lc rgb 'black' title 'noise (at rest before motion)'\n"
    << "set ylabel " << quoted(std::string(linear ? "σ_v (" : "σ_ω (") + unit + ")") << '\n'
    << "set title "
    << quoted(std::string("Speed uncertainty: fitted ") + (linear ? "log-normal" : "cubic") +
              " vs the de-skew error from ground truth")
    << '\n'
    << "plot $bins using 1:5 with points pt 7 ps 1.5 lc rgb '#1f4fbf' title 'measured Q3, noise removed (fitted)', \\\n"
    << "     sigma(x) with lines lw 2 lc rgb '#d62728' title 'fitted model', \\\n"
    << "     $bins using 1:7 with linespoints dt 2 pt 5 lc rgb '#2ca02c' title 'true de-skew error Q3', \\\n"
    << "     $bins using 1:6 with linespoints dt 3 pt 4 lc rgb '#2ca02c' title 'true de-skew error median'\n"
    << "unset multiplot\n";
  return s.str();
}

void draw_plot(const AxisCalibration& axis, const std::filesystem::path& png,
               const std::filesystem::path& script_path) {
  {
    std::ofstream out(script_path);
    out << plot_script(axis, png);
    if (!out.flush()) throw std::runtime_error(script_path.string() + ": cannot be written");
  }
  // The command line is constant; paths reach gnuplot only inside its own quoting.
  std::FILE* pipe = popen("gnuplot", "w");
  if (pipe == nullptr)
    throw std::runtime_error("cannot run gnuplot (install gnuplot-nox): " + png.string() + " not drawn");
  std::fprintf(pipe, "load %s\n", quoted(script_path.string()).c_str());
  const int status = pclose(pipe);
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error("gnuplot failed on " + script_path.string() + " (is gnuplot-nox installed?)");
}

}  // namespace tumble::calib
