// Checks shared by the motion tests: the reported derivatives must agree with
// central differences of the pose (and of the reported rates), and the peaks
// over a run must reach but never exceed configured limits.
#pragma once

#include "tools/sim/motion.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace tumble::sim::test {

struct DerivativeTolerance {
  double v_m_s = 1e-6;
  double a_m_s2 = 1e-3;
  double omega_rad_s = 1e-6;
  double alpha_rad_s2 = 2e-3;
};

// Body rate from R(t-h)^T R(t+h) = exp(2h [omega_b]) + O(h^3).
inline Eigen::Vector3d body_rate_by_difference(const Motion& m, double t, double h) {
  const Eigen::Matrix3d R0 = m.at(t - h).T_wb.linear();
  const Eigen::Matrix3d R1 = m.at(t + h).T_wb.linear();
  const Eigen::AngleAxisd d(R0.transpose() * R1);
  return d.axis() * d.angle() / (2 * h);
}

// Compares every reported derivative with a central difference at time t.
inline void expect_derivatives_at(const Motion& m, double t, const DerivativeTolerance& tol = {},
                                  double h = 1e-6) {
  const MotionState s = m.at(t);
  const MotionState lo = m.at(t - h), hi = m.at(t + h);
  const Eigen::Vector3d v_num = (hi.T_wb.translation() - lo.T_wb.translation()) / (2 * h);
  const Eigen::Vector3d a_num = (hi.v_w - lo.v_w) / (2 * h);
  const Eigen::Vector3d w_num = body_rate_by_difference(m, t, h);
  const Eigen::Vector3d al_num = (hi.omega_b - lo.omega_b) / (2 * h);
  EXPECT_LT((v_num - s.v_w).norm(), tol.v_m_s) << "velocity at t=" << t << ": " << s.v_w.transpose() << " vs "
                                               << v_num.transpose();
  EXPECT_LT((a_num - s.a_w).norm(), tol.a_m_s2) << "acceleration at t=" << t << ": " << s.a_w.transpose()
                                                << " vs " << a_num.transpose();
  EXPECT_LT((w_num - s.omega_b).norm(), tol.omega_rad_s) << "angular velocity at t=" << t << ": "
                                                         << s.omega_b.transpose() << " vs " << w_num.transpose();
  EXPECT_LT((al_num - s.alpha_b).norm(), tol.alpha_rad_s2) << "angular acceleration at t=" << t << ": "
                                                           << s.alpha_b.transpose() << " vs "
                                                           << al_num.transpose();
  // The rotation stays a rotation.
  const Eigen::Matrix3d R = s.T_wb.linear();
  EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-12) << "t=" << t;
}

// Evenly spread times plus the given extra ones (e.g. inside impacts).
inline void expect_derivatives(const Motion& m, int count, const std::vector<double>& extra = {},
                               const DerivativeTolerance& tol = {}) {
  const double h = 1e-6;
  std::vector<double> times = extra;
  for (int i = 0; i < count; ++i) times.push_back(h + (m.duration_s() - 2 * h) * (i + 0.5) / count);
  for (double t : times) expect_derivatives_at(m, t, tol, h);
}

struct Peaks {
  double speed_m_s = 0, accel_m_s2 = 0, rate_rad_s = 0, angular_accel_rad_s2 = 0;
};

// Peaks over a run: a coarse sweep, then a golden-section refinement
// around every coarse local maximum. coarse_s must be shorter than the
// narrowest bump of any norm (half a jolt, for |alpha|) so that every bump
// has a sample inside it. Every value reported
// is a real sample of the motion, so a peak can be missed but never invented.
inline Peaks sweep_peaks(const Motion& m, double coarse_s) {
  auto norms = [&m](double t) {
    const MotionState s = m.at(t);
    return std::array<double, 4>{s.v_w.norm(), s.a_w.norm(), s.omega_b.norm(), s.alpha_b.norm()};
  };
  std::vector<double> times;
  std::vector<std::array<double, 4>> q;
  for (double t = 0; t <= m.duration_s(); t += coarse_s) {
    times.push_back(t);
    q.push_back(norms(t));
  }
  std::array<double, 4> best{};
  for (const auto& n : q)
    for (int k = 0; k < 4; ++k) best[k] = std::max(best[k], n[k]);
  const double golden = (std::sqrt(5.0) - 1) / 2;
  for (std::size_t i = 1; i + 1 < q.size(); ++i) {
    for (int k = 0; k < 4; ++k) {
      // A real bump (falling on at least one side), not rounding jitter on a
      // plateau, whose value is sampled already. A peak between two samples
      // is inside the window around either of them.
      const double drop = q[i][k] - std::min(q[i - 1][k], q[i + 1][k]);
      if (!(q[i][k] >= q[i - 1][k] && q[i][k] >= q[i + 1][k] && drop > 1e-9 * q[i][k])) continue;
      // 30 steps shrink the window by 0.618^30 ~ 5e-7: the peak value is then
      // exact to ~1e-12 relative for pulses of a millisecond or more.
      double lo = times[i - 1], hi = times[i + 1];
      double a = hi - golden * (hi - lo), b = lo + golden * (hi - lo);
      double fa = norms(a)[k], fb = norms(b)[k];
      for (int iter = 0; iter < 30; ++iter) {
        best[k] = std::max({best[k], fa, fb});
        if (fa < fb) {  // the peak is in [a, hi]
          lo = a;
          a = b;
          fa = fb;
          b = lo + golden * (hi - lo);
          fb = norms(b)[k];
        } else {  // in [lo, b]
          hi = b;
          b = a;
          fb = fa;
          a = hi - golden * (hi - lo);
          fa = norms(a)[k];
        }
      }
      best[k] = std::max({best[k], fa, fb});
    }
  }
  return {best[0], best[1], best[2], best[3]};
}

}  // namespace tumble::sim::test
