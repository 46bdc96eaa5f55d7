#include "tools/calib/report.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "core/speed_uncertainty.hpp"

namespace tumble::calib {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const char* rig_name(Rig rig) { return rig == Rig::Rail ? "rail" : rig == Rig::Turntable ? "turntable" : "other"; }
const char* speed_unit(Rig rig) { return rig == Rig::Rail ? "m/s" : "rad/s"; }

std::ofstream open_for_writing(const std::filesystem::path& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path.string() + ": cannot be written");
  out.precision(9);
  return out;
}

void check_written(std::ofstream& out, const std::filesystem::path& path) {
  out.flush();
  if (!out) throw std::runtime_error(path.string() + ": write failed");
}

const AxisCalibration* axis_of(const Calibration& c, Rig rig) {
  if (rig == Rig::Rail && c.has_linear) return &c.linear;
  if (rig == Rig::Turntable && c.has_angular) return &c.angular;
  return nullptr;
}

void print_axis(std::FILE* out, const AxisCalibration& a) {
  const char* unit = speed_unit(a.rig);
  std::fprintf(
      out,
      "%s: %zu scans; noise: mean %.4f m, RMS %.4f m (medians of %zu scans at rest before motion), removed by %s\n",
      rig_name(a.rig), a.scans, a.noise.mean_m, a.noise.rms_m, a.noise.scans,
      a.noise.removal == NoiseRemoval::Quadrature ? "quadrature" : "subtraction");
  std::fprintf(out, "  %9s %6s %5s %10s %10s %10s | %10s %10s %10s | %9s %9s %7s\n", unit, "scans", "clip",
               "resid Q1 m", "median m", "Q3 m", "sigma Q3", "model", "true Q3", "model/Q3", "pred/true", "bounded");
  for (const BinSummary& b : a.bins) {
    if (b.centre == 0) {
      std::fprintf(out, "  %9.3f %6zu %5zu %10.5f %10.5f %10.5f | %10.5f %10s %10.5f |  (at rest: not fitted)\n",
                   b.speed_median, b.scans, b.saturated_scans, b.residual_m.q1, b.residual_m.median, b.residual_m.q3,
                   b.sigma.q3, "", b.deskew_sigma.q3);
      continue;
    }
    std::fprintf(out, "  %9.3f %6zu %5zu %10.5f %10.5f %10.5f | %10.5f %10.5f %10.5f | %9.3g %9.3g %6.0f%%%s\n",
                 b.speed_median, b.scans, b.saturated_scans, b.residual_m.q1, b.residual_m.median, b.residual_m.q3,
                 b.sigma.q3, b.model_sigma, b.deskew_sigma.q3, b.model_over_true_q3, b.predicted_over_true_median,
                 100 * b.bounded_fraction, b.in_fit ? "" : "  (not fitted)");
  }
  std::fprintf(out,
               "  check: model/true Q3 median over bins %.3g; over all moving scans median predicted/true de-skew "
               "error %.3g, bounded %.0f%%\n",
               a.model_over_true_q3_median, a.predicted_over_true_median, 100 * a.bounded_fraction);
}

}  // namespace

void write_residuals_csv(const std::filesystem::path& path, std::span<const RunOutcome> runs,
                         const Calibration& calibration, std::span<const double> rail_centres,
                         std::span<const double> turntable_centres) {
  std::ofstream out = open_for_writing(path);
  out << "run,rig,scan,t_start_s,duration_s,speed,speed_unit,bin_speed,mean_range_m,residual_m,residual_rms_m,residual_"
         "points,"
         "sigma,deskew_error_m,deskew_error_points,deskew_sigma,registered,saturated,before_motion\n";
  for (const RunOutcome& run : runs) {
    const AxisCalibration* axis = axis_of(calibration, run.rig);
    const std::span<const double> centres = run.rig == Rig::Rail ? rail_centres : turntable_centres;
    for (const ScanRecord& s : run.scans) {
      const bool usable = axis != nullptr && s.duration_s > 0 && s.mean_range_m > 0;
      const double sigma =
          usable ? sigma_from_residual(run.rig, axis->noise.skew_residual_m(s), s.duration_s, s.mean_range_m) : kNaN;
      const double deskew_sigma =
          usable ? sigma_from_residual(run.rig, s.deskew_error_m, s.duration_s, s.mean_range_m) : kNaN;
      out << run.name << ',' << rig_name(run.rig) << ',' << s.scan_index << ',' << s.t_start_s << ',' << s.duration_s
          << ',' << s.speed << ',' << speed_unit(run.rig) << ','
          << (centres.empty() ? kNaN : centres[bin_of(centres, s.speed)]) << ',' << s.mean_range_m << ','
          << s.residual_m << ',' << s.residual_rms_m << ',' << s.residual_points << ',' << sigma << ','
          << s.deskew_error_m << ',' << s.deskew_error_points << ',' << deskew_sigma << ',' << (s.registered ? 1 : 0)
          << ',' << (s.saturated ? 1 : 0) << ',' << (s.before_motion ? 1 : 0) << '\n';
    }
  }
  check_written(out, path);
}

void write_bins_csv(const std::filesystem::path& path, const Calibration& calibration) {
  std::ofstream out = open_for_writing(path);
  out << "rig,bin_speed,speed_median,speed_unit,scans,saturated_scans,duration_median_s,range_median_m,"
         "residual_q1_m,residual_median_m,residual_q3_m,noise_mean_m,noise_rms_m,sigma_q1,sigma_median,sigma_q3,"
         "deskew_error_q1_m,deskew_error_median_m,deskew_error_q3_m,deskew_sigma_q1,deskew_sigma_median,"
         "deskew_sigma_q3,in_fit,model_sigma,model_over_true_q3,predicted_over_true_median,bounded_fraction\n";
  for (const AxisCalibration* a : {axis_of(calibration, Rig::Rail), axis_of(calibration, Rig::Turntable)}) {
    if (a == nullptr) continue;
    for (const BinSummary& b : a->bins) {
      out << rig_name(a->rig) << ',' << b.centre << ',' << b.speed_median << ',' << speed_unit(a->rig) << ',' << b.scans
          << ',' << b.saturated_scans << ',' << b.duration_median_s << ',' << b.range_median_m << ',' << b.residual_m.q1
          << ',' << b.residual_m.median << ',' << b.residual_m.q3 << ',' << a->noise.mean_m << ',' << a->noise.rms_m
          << ',' << b.sigma.q1 << ',' << b.sigma.median << ',' << b.sigma.q3 << ',' << b.deskew_error_m.q1 << ','
          << b.deskew_error_m.median << ',' << b.deskew_error_m.q3 << ',' << b.deskew_sigma.q1 << ','
          << b.deskew_sigma.median << ',' << b.deskew_sigma.q3 << ',' << (b.in_fit ? 1 : 0) << ',' << b.model_sigma
          << ',' << b.model_over_true_q3 << ',' << b.predicted_over_true_median << ',' << b.bounded_fraction << '\n';
    }
  }
  check_written(out, path);
}

void write_calib_yaml(const std::filesystem::path& path, const Calibration& c) {
  std::ofstream out = open_for_writing(path);
  const SpeedUncertaintyParams paper;
  out << "# tumble-calib " << c.bench << ": speed-uncertainty models (paper section V-A), fitted to the\n"
      << "# third quartile of the de-skew residuals of " << (c.has_linear ? c.linear.scans : 0) << " rail and "
      << (c.has_angular ? c.angular.scans : 0) << " turntable scans.\n"
      << "# Merge into the registration: section of config/tumbled.yaml.\n"
      << "registration:\n";
  auto value = [&out](const char* key, double v, bool fitted, double paper_value, const std::string& note) {
    out << "  " << key << ": " << v << "  # ";
    if (fitted)
      out << "paper: " << paper_value;
    else
      out << "NOT FITTED (" << note << "): the paper's value";
    if (fitted && !note.empty()) out << "; " << note;
    out << '\n';
  };
  const bool lin = c.has_linear && c.linear.lognormal.fitted;
  const LognormalFit ln = c.has_linear ? c.linear.lognormal : LognormalFit{};
  const std::string ln_note = c.has_linear ? ln.note : "no rail run";
  value("lognormal_beta", ln.beta, lin, paper.lognormal_shape_beta, ln_note);
  value("lognormal_kappa_m_s", ln.kappa_m_s, lin, paper.lognormal_scale_kappa_m_s, ln_note);
  value("lognormal_lambda", ln.lambda, lin, paper.lognormal_gain_lambda, ln_note);
  const bool ang = c.has_angular && c.angular.cubic.fitted;
  const CubicFit cu = c.has_angular ? c.angular.cubic : CubicFit{};
  value("cubic_phi_rad_s", cu.phi_rad_s, ang, paper.cubic_scale_phi_rad_s,
        c.has_angular ? cu.note : "no turntable run");
  check_written(out, path);
}

void print_summary(std::FILE* out, const Calibration& c) {
  const SpeedUncertaintyParams paper;
  std::fprintf(out, "fitted (paper):\n");
  if (c.has_linear) {
    const LognormalFit& f = c.linear.lognormal;
    std::fprintf(
        out,
        "  lognormal_beta      %.4g (%.4g)\n  lognormal_kappa_m_s %.4g (%.4g)\n  lognormal_lambda    %.4g (%.4g)%s%s\n",
        f.beta, paper.lognormal_shape_beta, f.kappa_m_s, paper.lognormal_scale_kappa_m_s, f.lambda,
        paper.lognormal_gain_lambda, f.note.empty() ? "" : "  ", f.note.c_str());
  } else {
    std::fprintf(out, "  log-normal: no usable rail run\n");
  }
  if (c.has_angular) {
    std::fprintf(out, "  cubic_phi_rad_s     %.4g (%.4g)%s%s\n", c.angular.cubic.phi_rad_s, paper.cubic_scale_phi_rad_s,
                 c.angular.cubic.note.empty() ? "" : "  ", c.angular.cubic.note.c_str());
  } else {
    std::fprintf(out, "  cubic: no usable turntable run\n");
  }
  std::fprintf(
      out,
      "columns: bin median true speed; mean residual quartiles as measured; sigma Q3 = converted, noise "
      "removed (fitted); model = fitted curve; true Q3 = noise-free de-skew error converted; model/Q3 = model over "
      "true Q3 (1 = perfect); pred/true = median per-scan ratio predicted/true de-skew error; bounded = "
      "scans the curve bounds (perfect: 75%%)\n");
  if (c.has_linear) print_axis(out, c.linear);
  if (c.has_angular) print_axis(out, c.angular);
}

}  // namespace tumble::calib
