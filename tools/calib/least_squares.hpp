// A small Levenberg–Marquardt for the few-parameter curve fits (Eigen only):
// minimises Σ r_i(x)² given the residuals and their Jacobian. Marquardt's
// scaling (damping λ·diag(JᵀJ)) keeps it invariant to parameter units.
#pragma once

#include <Eigen/Core>
#include <functional>

namespace tumble::calib {

// Fills r (size m) and J (m × n) at x.
using ResidualFunction = std::function<void(const Eigen::VectorXd& x, Eigen::VectorXd& r, Eigen::MatrixXd& J)>;

struct LeastSquaresResult {
  Eigen::VectorXd x;
  double cost = 0;  // Σ r² at x
  int iterations = 0;
  bool converged = false;  // relative cost or step change below tolerance
};

LeastSquaresResult levenberg_marquardt(const ResidualFunction& f, const Eigen::VectorXd& x0, int max_iterations = 200,
                                       double tolerance = 1e-12);

}  // namespace tumble::calib
