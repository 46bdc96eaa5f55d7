#include "tools/calib/rig_lever_arm.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <vector>

namespace tumble::calib {
namespace {

constexpr int kUnknowns = 9;  // t, accelerometer bias, gravity

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Per IMU sample, in the lidar frame: time, attitude relative to the first
// sample (IMU frame), rate, angular acceleration, specific force.
struct ImuTrack {
  std::vector<double> t_s;
  std::vector<Eigen::Quaterniond> q_i;
  std::vector<Eigen::Vector3d> omega_l, alpha_l, f_l;
};

ImuTrack track_of(std::span<const ImuSample> imu, const GyroModel& gyro) {
  ImuTrack tr;
  const std::size_t n = imu.size();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  for (std::size_t j = 0; j < n; ++j) {
    const double t = imu[j].t_s + gyro.timing.offset_s;
    if (j > 0) q = (q * gyro_rotation(imu, gyro.timing, tr.t_s.back(), t)).normalized();
    tr.t_s.push_back(t);
    tr.q_i.push_back(q);
    tr.omega_l.push_back(gyro.R_li * (imu[j].gyro_rad_s - gyro.timing.bias_rad_s));
    tr.f_l.push_back(gyro.R_li * imu[j].accel_m_s2);
  }
  tr.alpha_l.assign(n, Eigen::Vector3d::Zero());
  for (std::size_t j = 1; j + 1 < n; ++j)
    tr.alpha_l[j] = (tr.omega_l[j + 1] - tr.omega_l[j - 1]) / (tr.t_s[j + 1] - tr.t_s[j - 1]);
  return tr;
}

}  // namespace

LeverArmEstimate estimate_lever_arm(std::span<const ScanPose> poses, std::span<const ImuSample> imu,
                                    const GyroModel& gyro, std::size_t half_span) {
  LeverArmEstimate out;
  if (imu.size() < 3 || poses.size() < 2 * half_span + 1 || half_span == 0) return out;
  const ImuTrack tr = track_of(imu, gyro);
  const Eigen::Matrix3d& R = gyro.R_li;

  std::vector<Eigen::Matrix<double, 3, kUnknowns>> rows;
  std::vector<Eigen::Vector3d> rhs;
  for (std::size_t k = half_span; k + half_span < poses.size(); ++k) {
    const ScanPose &pa = poses[k - half_span], &pb = poses[k], &pc = poses[k + half_span];
    if (!pa.registered || !pb.registered || !pc.registered) continue;
    const double a = pa.t_s, b = pb.t_s, c = pc.t_s;
    // Evenly spaced: no scan missing in between.
    if (!(b > a && c > b) || std::abs((c - b) - (b - a)) > 0.25 * (c - a) / static_cast<double>(2 * half_span))
      continue;
    const auto first = std::upper_bound(tr.t_s.begin(), tr.t_s.end(), a);
    const auto last = std::lower_bound(tr.t_s.begin(), tr.t_s.end(), c);
    if (first == tr.t_s.begin() || last == tr.t_s.end()) continue;  // the IMU must cover the window

    // Attitude of the IMU frame at b (relative to the track's start).
    const auto at_b = std::upper_bound(tr.t_s.begin(), tr.t_s.end(), b) - 1;
    const std::size_t jb = static_cast<std::size_t>(at_b - tr.t_s.begin());
    const Eigen::Quaterniond q_b = tr.q_i[jb] * gyro_rotation(imu, gyro.timing, tr.t_s[jb], b);
    const Eigen::Matrix3d R_wl_b = pb.T_wl.linear();

    Eigen::Matrix<double, 3, kUnknowns> A = Eigen::Matrix<double, 3, kUnknowns>::Zero();
    Eigen::Vector3d imu_side = Eigen::Vector3d::Zero();
    for (auto it = first; it != last; ++it) {
      const std::size_t j = static_cast<std::size_t>(it - tr.t_s.begin());
      const double s = tr.t_s[j];
      const double kernel = s <= b ? (s - a) / (b - a) : (c - s) / (c - b);
      const double dt = 0.5 * (tr.t_s[std::min(j + 1, tr.t_s.size() - 1)] - tr.t_s[j > 0 ? j - 1 : 0]);
      const double w = kernel * dt;
      const Eigen::Matrix3d R_wl = R_wl_b * R * (q_b.conjugate() * tr.q_i[j]).toRotationMatrix() * R.transpose();
      const Eigen::Matrix3d M = skew(tr.alpha_l[j]) + skew(tr.omega_l[j]) * skew(tr.omega_l[j]);
      A.block<3, 3>(0, 0) -= w * R_wl * M;
      A.block<3, 3>(0, 3) -= w * R_wl * R;
      A.block<3, 3>(0, 6) += w * Eigen::Matrix3d::Identity();
      imu_side += w * R_wl * tr.f_l[j];
    }
    const Eigen::Vector3d lidar_side = (pc.T_wl.translation() - pb.T_wl.translation()) / (c - b) -
                                       (pb.T_wl.translation() - pa.T_wl.translation()) / (b - a);
    rows.push_back(A);
    rhs.push_back(lidar_side - imu_side);
  }
  out.windows = rows.size();
  if (rows.size() * 3 <= kUnknowns + 3) return out;

  Eigen::Matrix<double, kUnknowns, kUnknowns> AtA = Eigen::Matrix<double, kUnknowns, kUnknowns>::Zero();
  Eigen::Matrix<double, kUnknowns, 1> Atb = Eigen::Matrix<double, kUnknowns, 1>::Zero();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    AtA += rows[i].transpose() * rows[i];
    Atb += rows[i].transpose() * rhs[i];
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, kUnknowns, kUnknowns>> eig(AtA);
  if (!(eig.eigenvalues()(0) > 1e-12 * eig.eigenvalues()(kUnknowns - 1))) return out;
  const Eigen::Matrix<double, kUnknowns, kUnknowns> AtA_inv = AtA.inverse();
  const Eigen::Matrix<double, kUnknowns, 1> x = AtA_inv * Atb;
  double ssr = 0.0;
  for (std::size_t i = 0; i < rows.size(); ++i) ssr += (rhs[i] - rows[i] * x).squaredNorm();
  const double dof = 3.0 * static_cast<double>(rows.size()) - kUnknowns;
  const double sigma2 = ssr / dof;
  out.solved = true;
  out.t_m = x.head<3>();
  out.accel_bias_m_s2 = x.segment<3>(3);
  out.gravity_m_s2 = x.tail<3>().norm();
  for (int i = 0; i < 3; ++i) out.sigma_m(i) = std::sqrt(sigma2 * AtA_inv(i, i));
  out.rms_residual_m_s = std::sqrt(ssr / (3.0 * static_cast<double>(rows.size())));
  return out;
}

}  // namespace tumble::calib
