#include "tools/calib/least_squares.hpp"

#include <Eigen/Cholesky>
#include <cmath>

namespace tumble::calib {

LeastSquaresResult levenberg_marquardt(const ResidualFunction& f, const Eigen::VectorXd& x0, int max_iterations,
                                       double tolerance) {
  LeastSquaresResult out;
  out.x = x0;
  Eigen::VectorXd r, r_new;
  Eigen::MatrixXd J, J_new;
  f(out.x, r, J);
  out.cost = r.squaredNorm();
  double lambda = 1e-3;
  for (out.iterations = 0; out.iterations < max_iterations; ++out.iterations) {
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    const Eigen::VectorXd diagonal = JtJ.diagonal().cwiseMax(1e-300);
    bool improved = false;
    while (lambda < 1e12) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal() += lambda * diagonal;
      const Eigen::VectorXd step = A.ldlt().solve(-g);
      const Eigen::VectorXd x_new = out.x + step;
      f(x_new, r_new, J_new);
      const double cost_new = r_new.squaredNorm();
      if (std::isfinite(cost_new) && cost_new <= out.cost) {
        const bool small_change = out.cost - cost_new <= tolerance * (out.cost + tolerance) ||
                                  step.norm() <= tolerance * (out.x.norm() + tolerance);
        out.x = x_new;
        out.cost = cost_new;
        r.swap(r_new);
        J.swap(J_new);
        lambda = std::max(lambda / 10, 1e-12);
        improved = true;
        if (small_change) {
          out.converged = true;
          ++out.iterations;
          return out;
        }
        break;
      }
      lambda *= 10;
    }
    if (!improved) {  // no step lowers the cost: at a minimum (to machine precision)
      out.converged = true;
      return out;
    }
  }
  return out;
}

}  // namespace tumble::calib
