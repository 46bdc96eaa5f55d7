#include "tools/calib/rig_rotation.hpp"

#include <Eigen/SVD>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace tumble::calib {
namespace {

constexpr int kRounds = 4;
// An increment is an outlier beyond this many times the median residual (a
// residual norm of 3 Gaussian axes has median ~1.5 σ, so this is ~6 σ).
constexpr double kOutlierFactor = 4.0;
// Never below this (rad): at rest the median residual is the registration's
// noise alone, and would reject every moving increment.
constexpr double kMinOutlierLimitRad = 0.003;

Eigen::Matrix3d kabsch(std::span<const RotationIncrement> increments, const std::vector<bool>& use,
                       const Eigen::Vector3d& bias) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < increments.size(); ++k) {
    if (!use[k]) continue;
    H += (increments[k].gyro_rad - bias * increments[k].dt_s) * increments[k].lidar_rad.transpose();
  }
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixV() * D * svd.matrixU().transpose();
}

Eigen::Vector3d bias_given(std::span<const RotationIncrement> increments, const std::vector<bool>& use,
                           const Eigen::Matrix3d& R_li) {
  Eigen::Vector3d num = Eigen::Vector3d::Zero();
  double den = 0.0;
  for (std::size_t k = 0; k < increments.size(); ++k) {
    if (!use[k]) continue;
    const RotationIncrement& inc = increments[k];
    num += inc.dt_s * (inc.gyro_rad - R_li.transpose() * inc.lidar_rad);
    den += inc.dt_s * inc.dt_s;
  }
  return den > 0 ? Eigen::Vector3d(num / den) : Eigen::Vector3d::Zero();
}

}  // namespace

double weakest_axis_excitation_rad2(std::span<const RotationIncrement> increments) {
  if (increments.empty()) return 0.0;
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (const RotationIncrement& inc : increments) S += inc.lidar_rad * inc.lidar_rad.transpose();
  S /= static_cast<double>(increments.size());
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(S).eigenvalues()(0);
}

HandEyeRotation align_rotation_increments(std::span<const RotationIncrement> increments, bool reject_outliers) {
  HandEyeRotation out;
  const std::size_t n = increments.size();
  if (n < 3 || weakest_axis_excitation_rad2(increments) <= 0.0) return out;
  std::vector<bool> use(n, true);
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
  std::vector<double> residual(n);
  for (int round = 0; round < (reject_outliers ? kRounds : 1); ++round) {
    for (int alternation = 0; alternation < 3; ++alternation) {
      R = kabsch(increments, use, bias);
      bias = bias_given(increments, use, R);
    }
    for (std::size_t k = 0; k < n; ++k)
      residual[k] = (increments[k].lidar_rad - R * (increments[k].gyro_rad - bias * increments[k].dt_s)).norm();
    std::vector<double> sorted;
    for (std::size_t k = 0; k < n; ++k)
      if (use[k]) sorted.push_back(residual[k]);
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    const double limit = std::max(kOutlierFactor * sorted[sorted.size() / 2], kMinOutlierLimitRad);
    if (reject_outliers)
      for (std::size_t k = 0; k < n; ++k) use[k] = residual[k] <= limit;
  }
  R = kabsch(increments, use, bias);
  bias = bias_given(increments, use, R);

  // Small-angle covariance: perturbing R by exp(δ) changes a residual by
  // -δ × (R r_I) = [R r_I]× δ.
  Eigen::Matrix3d JtJ = Eigen::Matrix3d::Zero();
  double ssr = 0.0;
  std::size_t used = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!use[k]) continue;
    const Eigen::Vector3d m = R * (increments[k].gyro_rad - bias * increments[k].dt_s);
    ssr += (increments[k].lidar_rad - m).squaredNorm();
    Eigen::Matrix3d skew;
    skew << 0, -m.z(), m.y(), m.z(), 0, -m.x(), -m.y(), m.x(), 0;
    JtJ += skew.transpose() * skew;
    ++used;
  }
  out.R_li = R;
  out.gyro_bias_rad_s = bias;
  out.used = used;
  out.inlier = use;
  out.sum_squared_residual_rad2 = ssr;
  out.rms_residual_rad = used > 0 ? std::sqrt(ssr / (3.0 * static_cast<double>(used))) : 0.0;
  const double dof = 3.0 * static_cast<double>(used) - 6.0;
  if (dof > 0 && JtJ.determinant() > 0) {
    const Eigen::Matrix3d cov = (ssr / dof) * JtJ.inverse();
    const double largest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues()(2);
    out.sigma_deg = std::sqrt(largest) * 180.0 / std::numbers::pi;
  }
  return out;
}

}  // namespace tumble::calib
